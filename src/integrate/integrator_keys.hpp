// The keys of [integrator] (declared next to the integrators they choose).
#pragma once
#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<SimulationSpec>& integrator_keys();

}  // namespace mesodpd
