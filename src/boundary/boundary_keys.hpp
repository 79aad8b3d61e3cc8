// The keys of [walls] and [poiseuille], declared next to the walls and fields they configure.
#pragma once
#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<WallsSpec>& walls_keys();
const keys::KeyTable<PoiseuilleSpec>& poiseuille_keys();

}  // namespace mesodpd
