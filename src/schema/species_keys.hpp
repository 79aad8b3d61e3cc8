// The keys of a [[species]] block, declared once for the reader, validate() and docs/config.md.
#pragma once
#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<SpeciesSpec>& species_keys();

}  // namespace mesodpd
