// The keys of [[bond_type]], [[angle_type]], [[molecule]] and [bonds] (exclusions, the reach of the ghost
// layer, multiple time stepping); their cross-checks are in src/schema/validate.cpp.
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

const keys::KeyTable<BondTypeSpec>& bond_type_keys() {
  using T = BondTypeSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("bond_type");
    t.string("name", &T::name, "Referred to by `molecule.bond_type`.")
      .required()
      .allowed("letters, digits, `_`; unique");
    t.choice("style", &T::style, {{"harmonic", BondStyleSpec::Harmonic}, {"fene", BondStyleSpec::Fene}, {"wlc", BondStyleSpec::Wlc}}, "`harmonic`: U = k/2 (r - r0)^2. `fene`: F = -k r / (1 - (r/rmax)^2) (seed 000 Eq. 27, H = k, r_m = rmax), U = -k rmax^2/2 ln(1 - (r/rmax)^2). `wlc`: F = -(kT / 4 lambda_p) [(1 - r/l)^-2 + 4 r/l - 1] (seed 000 Eq. 26, l = rmax, lambda_p = persistence, kT from `system.kT`). Each style reads its own keys; a key of another style is refused.")
      .required(" (\"harmonic\", \"fene\" or \"wlc\")")
      .selects("not used by style {value}", " (style {value} needs it)")
      .variant(BondStyleSpec::Harmonic, {"k"}, {"r0"})
      .variant(BondStyleSpec::Fene, {"k", "rmax"})
      .variant(BondStyleSpec::Wlc, {"persistence", "rmax"});
    t.number("k", &T::k, keys::kNonNegative, "Spring constant.");
    t.number("r0", &T::r0, keys::kNonNegative, "Rest length.")
      .allowed("[0, `bonds.reach`)");
    t.number("rmax", &T::rmax, keys::kPositive, "Maximum extension. A bond that reaches it stops the run (exit 3) naming the step, the bond number and its two particle ids.");
    t.number("persistence", &T::persistence, keys::kPositive, "Effective persistence length lambda_p.");
    return t;
  }();
  return table;
}

const keys::KeyTable<AngleTypeSpec>& angle_type_keys() {
  using T = AngleTypeSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("angle_type");
    t.string("name", &T::name, "Referred to by `molecule.angle_type`.")
      .required()
      .allowed("letters, digits, `_`; unique");
    t.choice("style", &T::style, {{"cosine", AngleStyleSpec::Cosine}}, "U = k [1 - cos(theta - theta0)] (seed 002 Eq. 32, Shillcock and Lipowsky), theta the angle between the two bond vectors r2 - r1 and r3 - r2: a straight triple has theta = 0 (LAMMPS measures the angle at the centre, pi - theta).");
    t.number("k", &T::k, keys::kNonNegative, "Bending stiffness (energy).")
      .required();
    t.number("theta0", &T::theta0_deg, {0.0, 180.0, true, true}, "Preferred angle.")
      .unit("degrees")
      .allowed("[0, 180] degrees");
    return t;
  }();
  return table;
}

const keys::KeyTable<DihedralTypeSpec>& dihedral_type_keys() {
  using T = DihedralTypeSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("dihedral_type");
    t.string("name", &T::name, "A dihedral type of a LAMMPS data file's `Dihedrals` section (type k there takes the k-th `[[dihedral_type]]` block).")
      .required()
      .allowed("letters, digits, `_`; unique");
    t.choice("style", &T::style, {{"cosine", DihedralStyleSpec::Cosine}}, "U = k [1 - cos(theta - theta0)], theta the angle between the normals of the triangles (a, b, c) and (d, c, b) of the dihedral a-b-c-d (central bond b-c), 0 when the four atoms lie flat with a and d on opposite sides: the Kantor-Nelson bending of a triangulated membrane (the `[[membrane]]` law). With theta0 = 0 it is LAMMPS's `dihedral_style harmonic` with K = k, d = +1, n = 1 (LAMMPS's phi is pi - theta).");
    t.number("k", &T::k, keys::kNonNegative, "Stiffness (energy); a membrane of bending rigidity kappa has k = 2 kappa / sqrt(3).")
      .required();
    t.number("theta0", &T::theta0_deg, {-180.0, 180.0, true, true}, "Preferred angle.")
      .unit("degrees")
      .allowed("[-180, 180] degrees");
    return t;
  }();
  return table;
}

const keys::KeyTable<MoleculeSpec>& molecule_keys() {
  using T = MoleculeSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("molecule");
    t.string("name", &T::name, "For messages and the chain measurements.")
      .required()
      .allowed("letters, digits, `_`");
    t.string("sequence", &T::sequence, "The beads, in the notation of seed 002 (\"Amphiphilic Systems\"): species names each followed by a count. `\"A10\"`: a linear chain of 10 A beads. `\"H1T4\"`: the amphiphile H T_4. `\"H3(T4)2\"`: H_3 (T_4)_2, two tails of 4 T beads both bonded to the last head bead. A parenthesised group must come last. Species names in a sequence must be letters (and `_`) only.")
      .required(" (e.g. \"A10\", \"H1T4\" or \"H3(T4)2\")")
      .allowed("see below");
    t.string("bond_type", &T::bond_type, "Type of every bond of the molecule.")
      .required()
      .allowed("a `[[bond_type]]` name");
    t.string("angle_type", &T::angle_type, "With it, every pair of bonds sharing a bead is an angle (a linear chain of N beads has N - 2; a branch point with three bonds has 3).")
      .allowed("an `[[angle_type]]` name");
    t.integer("count", &T::count, {}, "Number of molecules.")
      .default_text("one of count, density")
      .allowed(">= 0");
    t.number("density", &T::density, keys::kPositive, "Bead number density of this kind of molecule: count = round(density x volume / beads).");
    t.number("bond_length", &T::bond_length, keys::kPositive, "Step of the random walk that places each molecule: the first bead uniformly in the box, every further bead at this distance from the bead it is bonded to, in a uniformly random direction (a pure function of `system.seed` and the molecule number). On a bounded axis a step that would leave the box is drawn again, and with `[[solid]]` walls so is a bead closer than 0.5 to a solid or whose bond's midpoint lies in one (molecules are placed in the fluid, on top of the fluid's own density); a molecule that cannot be placed is refused naming the block. Beads may not be of a frozen species.")
      .allowed("(0, `bonds.reach`), and < rmax");
    return t;
  }();
  return table;
}

}  // namespace mesodpd
