// The keys of [[solid]], its shapes, [walls] and [poiseuille], declared next to the walls and fields they
// configure.
#pragma once
#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<WallsSpec>& walls_keys();
// A shape table: a [[solid]] block's shape keys, an element of its `parts`, a [[species]] region.
const keys::KeyTable<ShapeSpec>& shape_keys();
// The keys of a [[solid]] block besides its shape's.
const keys::KeyTable<SolidSpec>& solid_keys();
const keys::KeyTable<PoiseuilleSpec>& poiseuille_keys();

}  // namespace mesodpd
