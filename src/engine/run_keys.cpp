// The keys of the sections that describe the run as a whole ([system], [init], [run], [neighbor],
// [parallel], [output], [output.dump]); their cross-checks are in src/schema/validate.cpp.
#include "engine/run_keys.hpp"

#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<SimulationSpec>& system_keys() {
  using S = SimulationSpec;
  static const keys::KeyTable<S> table = [] {
    keys::KeyTable<S> t("system");
    t.vec3("box", &S::box, keys::kPositive, "Lengths of the orthorhombic box (periodic unless `periodic` says otherwise). The minimum-image convention needs every length to be at least twice the largest `rc`/`rd` of any species pair; otherwise the error names `system.box`. On more than one MPI rank every periodic length must also be at least 3 x (largest cutoff + skin), i.e. hold three neighbour cells (see `[parallel]`).")
      .required(" (three positive box lengths)")
      .allowed("each > 0 and >= 2 x the largest cutoff")
      .unit("r_c");
    t.bool3("periodic", &S::periodic, "Per axis x, y, z: periodic (`true`) or bounded (`false`). A bounded axis has no periodic images: pairs are not formed across its two faces, particles are not wrapped there, and no ghosts or particles cross it between MPI ranks. A bounded axis must be closed at both faces by solids at least `walls.depth` thick (see [Walls and solids](#walls-and-solids-solid-and-walls)); without any `[[solid]]` a `false` is refused (naming `species[k].body_force` when a body force pushes along that axis, `system.periodic` otherwise).")
      .allowed("a `false` needs `[[solid]]` walls closing both faces");
    t.number("kT", &S::kT, keys::kPositive, "Thermostat temperature k_BT. Enters the fluctuation-dissipation relation sigma^2 = 2 gamma kT (seed 000 Eq. 7).");
    t.integer("seed", &S::seed, {0}, "Seed of the counter-based pair noise and of the initial state. Same seed, same trajectory.");
    return t;
  }();
  return table;
}

const keys::KeyTable<SimulationSpec>& init_keys() {
  using S = SimulationSpec;
  static const keys::KeyTable<S> table = [] {
    keys::KeyTable<S> t("init");
    t.custom("lammps_data", "string", "none", "an existing file", "LAMMPS data file with the initial particles: atom styles `atomic`, `bond`, `angle`, `molecular` and `full` (charges must be zero), named after `Atoms` (`Atoms # molecular`) or known from the column count; also `edpd` (`id type edpd_temp edpd_cv x y z`: the particles' starting temperatures with pair.style = \"edpd\"; edpd_cv must equal the species' `cv`) and `tdpd` (`id type x y z cc1 .. ccN`, N = `[tdpd] solutes`: the starting concentrations with pair.style = \"tdpd\"), which must be named after `Atoms`; a wall held at a temperature or concentration must start at it, and NaN, a non-positive temperature or a negative concentration is refused naming the line; `Bonds`, `Angles` and `Dihedrals` sections give the topology (type k takes the k-th `[[bond_type]]`, `[[angle_type]]` or `[[dihedral_type]]` block; impropers and other styles are refused naming the line). Every coordinate must lie within the file's box bounds (`xlo` <= x <= `xhi`, ...): an atom outside is refused naming the line, not wrapped (unwrapped positions are given inside the box with image flags); atoms on periodic axes are then wrapped into [0, L). A FENE or worm-like-chain bond at or past its `rmax` stops the run at step 0 with exit code 3 (and `mesodpd check` with it), naming the bond, its atom ids and its length. A relative path is relative to the directory of the config file, not the working directory; it is stored as an absolute path.");
    t.choice("velocities", &S::velocities, {{"maxwell", VelocityInit::Maxwell}, {"file", VelocityInit::File}, {"zero", VelocityInit::Zero}}, "`maxwell`: Maxwell-Boltzmann at kT with zero total momentum. `file`: take the data file's `Velocities` section (requires `lammps_data`; a data file without a `Velocities` section is rejected with an error naming `init.velocities`, so set `\"maxwell\"` or `\"zero\"` for such a file). `zero`: all particles start at rest.")
      .default_text("`\"file\"` with `lammps_data`, else `\"maxwell\"`");
    return t;
  }();
  return table;
}

const keys::KeyTable<SimulationSpec>& run_keys() {
  using S = SimulationSpec;
  static const keys::KeyTable<S> table = [] {
    keys::KeyTable<S> t("run");
    t.integer("steps", &S::steps, {0}, "Number of time steps (the command line may override it).");
    t.choice("noise", &S::noise, {{"uniform", NoiseDistribution::Uniform}, {"gaussian", NoiseDistribution::Gaussian}}, "Distribution of the pair random numbers xi_ij, both with zero mean and unit variance; Groot and Warren found no statistical difference (seed 000 Sec. 2.5.1), uniform is cheaper.");
    t.number("max_velocity", &S::max_velocity, keys::kPositive, "Blow-up guard: the run stops with an error as soon as a particle's speed exceeds this.");
    t.number("max_density", &S::max_density, keys::kPositive, "Blow-up guard of `pair.style = \"mdpd\"`: the run stops (exit code 3) naming the step, the particle and its local density as soon as a local density from the density pass exceeds this (a collapsing liquid), before positions become NaN. Warren's liquid (a = -40, b = 25) stays below about 15.");
    t.number("max_temperature_ratio", &S::max_temperature_ratio, keys::kNonNegative, "Runaway guard: `mesodpd run` exits with code 3 (after writing every output) when the mean temperature over the second half of the run's thermo rows is more than this many times `system.kT`: such a run has run away (a time step too large for its forces, or forces too strong to integrate) and its numbers are not to be trusted. The temperature is the one of the end-of-run warning: across the flow with `[poiseuille]`, relative to the local flow with walls. Judged only for runs of at least 2 time units (steps x dt of this run): a shorter one may still carry the heat of a random start and gets the warning only. 0 switches the check off, for runs meant to heat up.");
    t.integer("threads", &S::threads, {0, kMaxThreads}, "OpenMP threads (per MPI rank); 0 uses the OpenMP default (all cores, or `OMP_NUM_THREADS`). By design, results do not depend on it. `mesodpd run --threads N` overrides it (same range).");
    return t;
  }();
  return table;
}

const keys::KeyTable<SimulationSpec>& neighbor_keys() {
  using S = SimulationSpec;
  static const keys::KeyTable<S> table = [] {
    keys::KeyTable<S> t("neighbor");
    t.choice("method", &S::neighbor, {{"verlet", NeighborMethod::Verlet}, {"cells", NeighborMethod::Cells}}, "`cells`: particles are binned and sorted by cell and the pair list is rebuilt from the cells every step (no skin). `verlet`: a list with a skin, rebuilt only when some particle has moved half the skin. DPD particles move fast, so at dt = 0.04 a skin of 0.3 is exceeded by some particle almost every step and `cells` is faster; see `docs/performance.md`.");
    t.number("skin", &S::skin, {0, 2, true, true}, "Verlet-list skin added to the largest cutoff (`verlet` only).");
    return t;
  }();
  return table;
}

const keys::KeyTable<SimulationSpec>& parallel_keys() {
  using S = SimulationSpec;
  static const keys::KeyTable<S> table = [] {
    keys::KeyTable<S> t("parallel");
    t.ints3("grid", &S::parallel_grid, {0, 65536}, "ranks (0 = choose)", "Ranks along x, y, z. A 0 entry is chosen automatically; the automatic choice minimises the ghost volume per rank. The product of the entries must equal the number of ranks; with some entries 0, the others must be part of a factorisation of it.")
      .allowed("each 0 to 65536 (whole numbers)");
    return t;
  }();
  return table;
}

const keys::KeyTable<SimulationSpec>& output_keys() {
  using S = SimulationSpec;
  static const keys::KeyTable<S> table = [] {
    keys::KeyTable<S> t("output");
    t.subtable("dump");
    t.integer("thermo_every", &S::thermo_every, {1}, "Interval of thermodynamic output (temperature, pressure, energy).");
    t.integer("checkpoint_every", &S::checkpoint_every, {0}, "Checkpoint interval; 0 writes one only at the end.");
    t.boolean("progress", &S::progress, "Show a progress line on the terminal.");
    return t;
  }();
  return table;
}

const keys::KeyTable<DumpSpec>& dump_keys() {
  using D = DumpSpec;
  static const keys::KeyTable<D> table = [] {
    keys::KeyTable<D> t("output.dump");
    t.choice("format", &D::format, {{"lammps", DumpFormat::Lammps}, {"gsd", DumpFormat::Gsd}}, "LAMMPS text dump or HOOMD GSD.");
    t.integer("every", &D::every, {1}, "Frame interval in steps.");
    t.strings("fields", &D::fields, "Per-particle data written. `mol`: the molecule id (LAMMPS dump column `mol`, read by OVITO as Molecule Identifier; GSD `log/particles/mol`). A GSD file also holds the bonds and angles (`bonds/*`, `angles/*` chunks of its first frame), so OVITO and VMD draw the chains.")
      .allowed("non-empty subset of `id`, `species`, `position`, `velocity`, `force`, `image`, `mol` (and of any further per-particle field the build flags for frames, see architecture.md), no repeats");
    t.string("file", &D::file, "Output file name, relative to the output directory.")
      .default_text("`trajectory.lammpstrj` / `trajectory.gsd`")
      .allowed("non-empty");
    return t;
  }();
  return table;
}

}  // namespace mesodpd
