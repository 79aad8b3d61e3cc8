// The keys of [bonds]: exclusions, the reach of the ghost layer, multiple time stepping.
#include "engine/bonded_keys.hpp"

namespace mesodpd {

const keys::KeyTable<SimulationSpec>& bonds_keys() {
  using S = SimulationSpec;
  static const keys::KeyTable<S> table = [] {
    keys::KeyTable<S> t("bonds");
    t.choice("exclude", &S::bond_exclusion, {{"none", BondExclusion::None}, {"1-2", BondExclusion::OneTwo}, {"1-3", BondExclusion::OneThree}}, "Which bonded pairs lose their pair (DPD) force, like LAMMPS's `special_bonds` with factors 0: `none` keeps the DPD force between bonded beads (usual DPD practice); `1-2` removes it for bonded pairs; `1-3` also for pairs two bonds apart. The dissipative and random parts go with the conservative one.");
    t.number("reach", &S::bond_reach_set, keys::kCutoff, "How far the ghost layer of a rank reaches at least: neighbour cells are at least max(largest cutoff, reach) + skin wide. A bonded partner must be held by the rank that evaluates the bond; under MPI a bond (or angle leg) that stretches beyond the ghost layer stops the run (exit 3) naming the step, the bond and its ids. On one rank every partner is held and nothing is refused. Soft springs (e.g. harmonic k = 4) stretch past 1.0 often, especially while a random start relaxes: raise `reach` (it costs pair-loop time: wider cells hold more candidates) or use stiffer bonds.")
      .default_text("the largest pair cutoff")
      .allowed("[largest cutoff, 10]");
    t.integer("subcycles", &S::bond_subcycles, {1, 1000}, "Multiple time stepping (r-RESPA; seed 002's \"subcycling\" for stiff bonds): with n > 1 the bonded forces (bonds and angles) are integrated with n velocity-Verlet inner steps of `integrator.dt / n` inside each step, while the pair forces and external fields kick once per step (half before, half after). 1: the bonded forces are summed with the others in the one Groot-Warren step. Needs `integrator.type = \"groot-warren\"` and some bonds; not available with `[[solid]]` walls yet (their reflections predict a whole step's move). With n > 1 the `force` written to dumps, snapshots and checkpoints is the non-bonded part only (pair forces, exclusion corrections, external fields); the pressure tensor still includes the bonded virial. Validation: `docs/validation.md`, section 7.");
    return t;
  }();
  return table;
}

}  // namespace mesodpd
