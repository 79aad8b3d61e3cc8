// The keys of the sections that describe the run as a whole: [system], [init], [run], [neighbor],
// [parallel], [output] and [output.dump] (declared next to the Simulation that reads them).
#pragma once
#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<SimulationSpec>& system_keys();
const keys::KeyTable<SimulationSpec>& init_keys();
const keys::KeyTable<SimulationSpec>& run_keys();
const keys::KeyTable<SimulationSpec>& neighbor_keys();
const keys::KeyTable<SimulationSpec>& parallel_keys();
const keys::KeyTable<SimulationSpec>& output_keys();
const keys::KeyTable<DumpSpec>& dump_keys();

}  // namespace mesodpd
