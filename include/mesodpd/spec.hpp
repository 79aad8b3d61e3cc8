// The typed, validated description of a simulation. A TOML file (io/config) or an API call becomes
// a SimulationSpec before any engine object is built; the engine never reads raw configuration.
// Units: DPD reduced units (lengths in r_c, masses in particle mass, energies in k_BT).
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mesodpd {

// A configuration problem, always naming the offending key, file or value.
class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(const std::string& what, std::string key = {})
      : std::runtime_error(what), key_(std::move(key)) {}
  // The full key the problem is about, as the TOML schema spells it ("pair.override[1].rd"), where the
  // error is about one key (the TOML reader and validate() set it); empty otherwise.
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

enum class Placement { Lattice, Random };
enum class IntegratorKind { GrootWarren, Euler };
enum class NoiseDistribution { Uniform, Gaussian };
enum class NeighborMethod { Verlet, Cells };
enum class DumpFormat { Lammps, Gsd };
// The pair force law of a run (engine/pair_laws.hpp holds the list): standard DPD, or the soft cosine
// potential (physics/soft_pair.hpp), which uses a and rc of each PairSpec and no thermostat.
enum class PairStyle { Dpd, Soft };
enum class VelocityInit { Maxwell, File, Zero };

struct SpeciesSpec {
  std::string name;                            // [[species]] name
  double mass = 1.0;                           // [[species]] mass (> 0)
  std::optional<double> a;                     // [[species]] a, used by mixing = "geometric"
  std::array<double, 3> body_force{0, 0, 0};   // [[species]] body_force: constant external force
  std::optional<double> density;               // [[species]] density: when set, validate() sets count
  std::uint64_t count = 0;                     // [[species]] count, or round(density x box volume)
  Placement placement = Placement::Random;     // [[species]] placement
};

// DPD pair parameters as written ([pair] or one [[pair.override]]); an unset member falls back to the
// next level (override -> [pair] -> built-in default) when validate() resolves `SimulationSpec::pairs`.
struct PairParams {
  std::optional<double> a;      // conservative repulsion a_ij (default 25, or geometric mixing)
  std::optional<double> gamma;  // dissipative strength (default 4.5)
  std::optional<double> sigma;  // optional cross-check: sigma^2 = 2 gamma kT (seed 000 Eq. 7)
  std::optional<double> rc;     // conservative cutoff (default 1)
  std::optional<double> rd;     // dissipative/random cutoff (default: this pair's rc)
  std::optional<double> s;      // weight exponent (default 2)
};

enum class Mixing { Explicit, Geometric };

struct PairOverride {
  std::vector<std::string> species;  // the two species names of the pair, either order
  PairParams params;
};

// The [pair] table: defaults for every pair, the mixing rule for a_ij and the per-pair overrides.
struct PairSection {
  Mixing mixing = Mixing::Explicit;
  PairParams params;
  std::vector<PairOverride> overrides;  // [[pair.override]]
};

// Fully resolved interaction of one unordered species pair (i <= j), filled by validate().
struct PairSpec {
  int i = 0, j = 0;
  double a = 25.0, gamma = 4.5, rc = 1.0, rd = 1.0, s = 2.0;
};

// Reverse (periodic) Poiseuille flow of Backer et al. (seed 002 "Boundary Conditions"):
// force +g along flow_axis where the gradient coordinate is in the lower half, -g in the upper half.
struct PoiseuilleSpec {
  bool enabled = false;
  double force = 0.0;             // g, per unit mass (acceleration)
  int flow_axis = 0;              // 0 = x
  int gradient_axis = 2;          // 2 = z
  int bins = 40;                  // profile bins along the gradient axis
  std::uint64_t start = 0;        // steps before profile sampling starts (equilibration)
  std::uint64_t every = 1;        // sampling interval
  int blocks = 10;                // blocks for the viscosity error bar
};

struct RdfSpec {
  bool enabled = false;
  int bins = 100;
  double rmax = 3.0;
  std::uint64_t start = 0, every = 100;
};

struct MsdSpec {
  bool enabled = false;
  std::uint64_t start = 0, every = 100;
};

// Time-averaged fields on a grid of bins ([analysis.fields], repeatable as [[analysis.fields]]; issue 10
// item 5, issue 11 item 3): number density per species, mass-weighted velocity and the temperature of the
// peculiar velocity, on a 1-, 2- or 3-D grid over the box or a box-aligned sub-region.
enum class FieldsFit { None, Slab };
struct FieldsSpec {
  std::string name = "fields";                // output files <name>.vti, .csv, .json (unique per run)
  std::array<int, 3> bins{1, 1, 1};           // bins along x, y, z; 1 averages over that axis
  std::optional<std::array<double, 3>> lo, hi;  // sub-region as written (default: the whole box)
  std::array<double, 3> region_lo{0, 0, 0};   // resolved by validate(): lo, or 0
  std::array<double, 3> region_hi{0, 0, 0};   // resolved by validate(): hi, or the box length
  std::uint64_t start = 0, every = 10;        // first sampled step and interval
  std::vector<std::string> species;           // species in velocity, temperature, density (empty: all)
  std::vector<std::string> exclude;           // or: every species but these (e.g. frozen walls)
  std::vector<int> selected;                  // resolved by validate(): indices of the species binned
  int centre_axis = -1;                       // shift each sample so the selected mass is centred (-1: no)
  FieldsFit fit = FieldsFit::None;            // "slab": tanh fit of a 1-D density profile
  int blocks = 10;                            // blocks for the slab fit's error bars (B..2B-1 used)
  std::uint64_t write_every = 0;              // also write the files at these steps (0: at the end only)
};

struct DumpSpec {
  bool enabled = false;
  DumpFormat format = DumpFormat::Lammps;
  std::uint64_t every = 1000;
  std::vector<std::string> fields{"id", "species", "position"};  // id, species, position, velocity, force, image
  std::string file;  // relative to the output directory; validate() fills trajectory.lammpstrj / .gsd
};

// [[bond_type]]: one bond law and its parameters (physics/bond_laws.hpp). Types are numbered in
// file order from 1 (the type numbers of a LAMMPS data file's Bonds section).
enum class BondStyleSpec { Harmonic, Fene, Wlc };
struct BondTypeSpec {
  std::string name;
  BondStyleSpec style = BondStyleSpec::Harmonic;
  double k = 0;                  // harmonic, fene: spring constant
  double r0 = 0;                 // harmonic: rest length
  double rmax = 0;               // fene: r_m (seed 000 Eq. 27); wlc: maximum segment length l (Eq. 26)
  double persistence = 0;        // wlc: effective persistence length lambda_p
};

// [[angle_type]]: U = k [1 - cos(theta - theta0)] (seed 002 Eq. 32), theta between the bond vectors.
struct AngleTypeSpec {
  std::string name;
  double k = 0;
  double theta0_deg = 0;  // theta0 in degrees (0: straight)
};

// [[molecule]]: a molecule built by the config. `sequence` in the notation of seed 002 ("Amphiphilic
// Systems"): species names with counts, e.g. "A10" (a chain of 10 A beads), "H1T4" (amphiphile H T_4),
// "H3(T4)2" (two tails of 4 T beads, both bonded to the last head bead). Placed as random walks.
struct MoleculeSpec {
  std::string name;
  std::string sequence;
  std::vector<int> beads;                          // species index of every bead (set by validate())
  std::vector<std::array<int, 2>> bonds;           // bead index pairs within the molecule (validate())
  std::vector<std::array<int, 3>> angles;          // bead index triples, centre in the middle (validate())
  std::string bond_type;                           // name of a [[bond_type]]
  std::string angle_type;                          // name of an [[angle_type]], empty: no angles
  int bond_type_index = -1, angle_type_index = -1;  // set by validate()
  std::optional<double> density;                   // bead number density of this molecule kind, or
  std::uint64_t count = 0;                         // number of molecules (validate() sets it from density)
  double bond_length = 0.7;                        // random-walk step of the placement
};

// [bonds]: treatment of bonded pairs by the pair force (LAMMPS special_bonds with factors 0 or 1).
enum class BondExclusion { None, OneTwo, OneThree };

struct SimulationSpec {
  std::string source;                           // file the spec came from (for messages)
  std::array<double, 3> box{10, 10, 10};        // [system] box: orthorhombic box lengths
  std::array<bool, 3> periodic{true, true, true};  // [system] periodic: per axis periodic, or bounded (false)
  double kT = 1.0;                              // [system] kT
  std::uint64_t seed = 1;                       // [system] seed
  std::vector<SpeciesSpec> species;             // [[species]]
  PairStyle pair_style = PairStyle::Dpd;        // [pair] style
  PairSection pair_section;                     // [pair] and [[pair.override]] as written
  std::vector<PairSpec> pairs;                  // all n(n+1)/2 pairs, resolved by validate()
  std::string data_file;                        // [init] lammps_data: read particles from this file
  bool init_velocities = true;                  // set by validate(): velocities == Maxwell
  VelocityInit velocities = VelocityInit::Maxwell;  // [init] velocities; init_velocities == (Maxwell)

  IntegratorKind integrator = IntegratorKind::GrootWarren;  // [integrator] type
  double dt = 0.04;                             // [integrator] dt
  double lambda = 0.5;                          // [integrator] lambda (seed 000 Eq. 10)

  NoiseDistribution noise = NoiseDistribution::Uniform;  // [run] noise
  std::uint64_t steps = 1000;                   // [run] steps
  double max_velocity = 1.0e3;                  // [run] max_velocity: blow-up threshold on |v|
  int threads = 0;                              // [run] threads (0 = OpenMP default)

  NeighborMethod neighbor = NeighborMethod::Cells;  // [neighbor] method
  double skin = 0.3;                            // [neighbor] skin (verlet only)
  std::array<int, 3> parallel_grid{0, 0, 0};    // [parallel] grid: MPI ranks along x, y, z (0 = choose)

  std::uint64_t thermo_every = 100;             // [output] thermo_every
  std::uint64_t checkpoint_every = 0;           // [output] checkpoint_every (0 = only at the end)
  bool progress = true;                         // [output] progress
  DumpSpec dump;                                // [output.dump]
  PoiseuilleSpec poiseuille;                    // [poiseuille]
  RdfSpec rdf;                                  // [analysis.rdf]
  MsdSpec msd;                                  // [analysis.msd]
  std::vector<BondTypeSpec> bond_types;         // [[bond_type]]
  std::vector<AngleTypeSpec> angle_types;       // [[angle_type]]
  std::vector<MoleculeSpec> molecules;          // [[molecule]]
  BondExclusion bond_exclusion = BondExclusion::None;  // [bonds] exclude
  std::optional<double> bond_reach_set;         // [bonds] reach as written
  double bond_reach = 0;                        // longest bond or angle leg allowed; validate(): default the
                                                // largest pair cutoff. Neighbour cells (and so ghost layers)
                                                // are at least max(cutoff, reach) + skin wide.
  std::vector<FieldsSpec> fields;               // [analysis.fields] / [[analysis.fields]]

  // Index into `pairs` for species i, j (either order).
  const PairSpec& pair(int a, int b) const {
    const int i = a < b ? a : b, j = a < b ? b : a;
    const int n = static_cast<int>(species.size());
    return pairs[static_cast<std::size_t>(i * n - i * (i - 1) / 2 + (j - i))];
  }
};

}  // namespace mesodpd
