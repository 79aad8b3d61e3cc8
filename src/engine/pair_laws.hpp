// The compile-time list of pair force laws the engine can run, and their parameter tables built from a
// spec. Adding a law: its header in src/physics/, one entry in PairLawTables, one case in
// make_pair_laws (docs/architecture.md, "Add a pair force law").
#pragma once
#include <variant>

#include "mesodpd/spec.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/pair_table.hpp"
#include "physics/soft_pair.hpp"

namespace mesodpd {

// One law with its per-species-pair parameters (double; the pair loop converts them to its arithmetic type).
template <class Law>
struct LawTable {
  using LawType = Law;
  PairTable<typename Law::template Params<double>> table;
};

// Every law the shared pair loop is instantiated for (per SIMD target), in the order of PairStyle.
using PairLawTables = std::variant<LawTable<DpdLaw>, LawTable<SoftLaw>>;

// The law and parameter table of a validated spec (sigma from the fluctuation-dissipation relation).
PairLawTables make_pair_laws(const SimulationSpec& spec);
// The DPD table of a spec (the conservative part also serves the g(r) pressure integral).
PairTable<DpdPairParams> make_pair_table(const SimulationSpec& spec);

inline double max_cutoff(const PairLawTables& laws) {
  return std::visit([](const auto& t) { return t.table.max_cutoff; }, laws);
}

}  // namespace mesodpd
