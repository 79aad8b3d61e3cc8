// The typed, validated description of a simulation. A TOML file (io/config) or an API call becomes
// a SimulationSpec before any engine object is built; the engine never reads raw configuration.
// Units: DPD reduced units (lengths in r_c, masses in particle mass, energies in k_BT).
#pragma once
#include <any>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mesodpd/config_error.hpp"

namespace mesodpd {

// The most OpenMP threads a run accepts (run.threads, --threads): more is a typo, not a request.
inline constexpr int kMaxThreads = 1024;

enum class Placement { Lattice, Random };
enum class IntegratorKind { GrootWarren, Euler };
enum class NoiseDistribution { Uniform, Gaussian };
enum class NeighborMethod { Verlet, Cells };
enum class DumpFormat { Lammps, Gsd };
// The pair force law of a run: its index in the law list (PairLawTables, engine/pair_laws.hpp), whose
// laws declare their style names and keys (physics/law_keys.hpp). The enumerators name the built-in laws:
// standard DPD; the soft cosine potential (physics/soft_pair.hpp); many-body DPD (physics/mdpd_pair.hpp);
// Liu's spline potentials (physics/spline_pair.hpp). A law added to the list takes the next index.
enum class PairStyle : int { Dpd, Soft, Mdpd, Spline };
// The local-density kernel of many-body DPD (physics/density_kernel.hpp): Warren's or Lucy's.
enum class DensityKernelChoice { Warren, Lucy, Wendland };
enum class VelocityInit { Maxwell, File, Zero };

// One solid shape as a signed distance (negative inside the solid), src/boundary/geometry.hpp; also the
// region a generated species is placed in ([[species]] region).
enum class ShapeKind { Plane, Cylinder, Sphere, Box, Pillars, Image, Union, Difference };
enum class Lattice { Square, Hexagonal };
struct ShapeSpec {
  ShapeKind kind = ShapeKind::Plane;
  std::array<double, 3> point{0, 0, 0};      // plane: a point of the surface; pillars: lattice origin
  std::array<double, 3> normal{0, 0, 1};     // plane: unit normal pointing into the fluid
  std::array<double, 3> center{0, 0, 0};     // cylinder, sphere
  std::array<double, 3> direction{0, 0, 1};  // cylinder: axis direction (any, normalised by validate)
  double radius = 0.0;                       // cylinder, sphere, pillars
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};  // box corners
  Lattice lattice = Lattice::Square;         // pillars
  double spacing = 0.0;                      // pillars: centre-to-centre distance L
  int axis = 2;                              // pillars: pillar axis; image: extrusion axis of a 2-D image
  std::string file;                          // image: PGM (2-D, extruded) or MESODPD-VOXELS (3-D) file
  double voxel_size = 0.0;                   // image: edge of one pixel/voxel (image extent == box)
  bool invert = false;                       // image: swap solid and fluid
  std::vector<ShapeSpec> parts;              // union, difference (first minus the others)
};

struct SpeciesSpec {
  std::string name;                            // [[species]] name
  double mass = 1.0;                           // [[species]] mass (> 0)
  std::optional<double> a;                     // [[species]] a, used by mixing = "geometric"
  std::array<double, 3> body_force{0, 0, 0};   // [[species]] body_force: constant external force
  std::optional<double> density;               // [[species]] density: when set, validate() sets count
  std::uint64_t count = 0;                     // [[species]] count, or round(density x box volume)
  Placement placement = Placement::Random;     // [[species]] placement
  bool frozen = false;                         // [[species]] frozen: wall particles, never integrated
  // [[species]] region: generated particles of this species are kept only inside this shape (signed
  // distance < 0) or inside a [[solid]] (they become its wall particles); count/density are of the box.
  std::optional<ShapeSpec> region;
  // The pair law's species keys (physics/law_keys.hpp, kSpeciesOwn: eDPD's cv and temperature) as
  // written; validate() adds the law's defaults, so afterwards every key of the style's law is here.
  std::map<std::string, double, std::less<>> own;
};

// Pair parameters as written ([pair] or one [[pair.override]]); an unset member falls back to the
// next level (override -> [pair] -> the law's default) when validate() resolves `SimulationSpec::pairs`.
// The shared DPD keys have members; the keys a law declares for itself (physics/law_keys.hpp: b of
// "mdpd", repulsion, rc1, attraction, rc2 of "spline") are in `own`, by key name.
struct PairParams {
  std::optional<double> a;      // conservative repulsion a_ij (default 25, or geometric mixing)
  std::optional<double> gamma;  // dissipative strength (default 4.5)
  std::optional<double> sigma;  // optional cross-check: sigma^2 = 2 gamma kT (seed 000 Eq. 7)
  std::optional<double> rc;     // conservative cutoff (default 1)
  std::optional<double> rd;     // dissipative/random cutoff (default: this pair's rc)
  std::optional<double> s;      // weight exponent (default 2)
  std::map<std::string, double, std::less<>> own;  // a law's own keys, as written
};

enum class Mixing { Explicit, Geometric };

struct PairOverride {
  std::vector<std::string> species;  // the two species names of the pair, either order
  PairParams params;
};

// The [pair] table: defaults for every pair, the mixing rule for a_ij and the per-pair overrides.
struct PairSection {
  Mixing mixing = Mixing::Explicit;
  std::optional<DensityKernelChoice> kernel;  // [pair] kernel (laws with a density pass; default: the law's)
  PairParams params;
  std::vector<PairOverride> overrides;  // [[pair.override]]
};

// Fully resolved interaction of one unordered species pair (i <= j), filled by validate().
// With pair.style = "mdpd", rd is the many-body range r_d (seed 000 Eq. 17) and the dissipative and
// random forces act over rc. `own` holds every own key of the style's law (physics/law_keys.hpp), e.g.
// b (B_ij) of "mdpd" or repulsion/rc1/attraction/rc2 (A, r_c1, B, r_c2 of seed 000 Eq. 19) of "spline".
struct PairSpec {
  int i = 0, j = 0;
  double a = 25.0, gamma = 4.5, rc = 1.0, rd = 1.0, s = 2.0;
  std::map<std::string, double, std::less<>> own;

  // The value of one of the law's own keys (0 when the law has no such key).
  double value(std::string_view key) const {
    const auto it = own.find(key);
    return it == own.end() ? 0.0 : it->second;
  }
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
  std::vector<std::string> means;             // per-particle fields (double) averaged per bin: "temp" (eDPD)
};

// Surface tension of planar interfaces normal to `axis` from the pressure tensor of each thermo row at
// or after `start`: sigma = (L / 2) <P_nn - (P_tt + P_t't')/2> with a block error bar
// ([analysis.surface_tension]; analysis/surface_tension.hpp).
struct SurfaceTensionSpec {
  bool enabled = false;
  int axis = 2;                 // normal of the interfaces: 0 = x, 1 = y, 2 = z
  std::uint64_t start = 0;      // first thermo row used (equilibration before it)
  int blocks = 10;              // blocks of the error bar
};

// A droplet in its vapour ([analysis.droplet]; analysis/droplet.hpp): every `every` steps from `start`,
// the drop's centre, its radial density profile, the equimolar radius, and the pressure inside (particles
// within inner_radius of the centre) and outside (beyond outer_radius) from the per-particle virial of
// the conservative forces (seed 000 Eq. 24), for Laplace's law Delta P = 2 sigma / R.
struct DropletSpec {
  bool enabled = false;
  std::uint64_t start = 0, every = 100;  // first sampled step and interval
  double inner_radius = 0;               // required: the liquid core, well inside the drop
  double outer_radius = 0;               // required: the vapour beyond it (< half the smallest box length)
  double bin_width = 0.1;                // radial profile bins
  int blocks = 10;                       // blocks of the error bars
};

// How a pair's (or bond's, or angle leg's) virial r_ij (x) F_ij is shared out over the bins of a stress
// profile: "contour" spreads it along the straight line from j to i in proportion to the length of the
// line in each bin (Irving-Kirkwood with the straight contour; the form used for planar membranes);
// "half" puts half into the bin of each particle.
enum class StressAssignment : int { Contour = 0, Half = 1 };

// The pressure tensor binned along an axis ([analysis.stress_profile]; analysis/stress_profile.hpp):
// every `every` steps from `start`, kinetic m v v plus the configurational virial of the conservative
// pair forces, bonds and angles, in `bins` slabs normal to `axis`; p_N, p_T and the tension integral
// gamma = int (p_N - p_T) dz with a block error bar.
struct StressProfileSpec {
  bool enabled = false;
  int axis = 2;                          // normal of the slabs: 0 = x, 1 = y, 2 = z
  int bins = 50;
  std::uint64_t start = 0, every = 100;  // first sampled step and interval
  int blocks = 10;                       // blocks of the error bars
  StressAssignment assignment = StressAssignment::Contour;
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
enum class AngleStyleSpec { Cosine };
struct AngleTypeSpec {
  std::string name;
  AngleStyleSpec style = AngleStyleSpec::Cosine;  // the one angle law
  double k = 0;
  double theta0_deg = 0;  // theta0 in degrees (0: straight)
};

// [[dihedral_type]]: U = k [1 - cos(theta - theta0)], theta the hinge angle between the normals of the
// triangles (a, b, c) and (d, c, b) (Kantor-Nelson; physics/bond_laws.hpp). Dihedrals come from a LAMMPS
// data file's Dihedrals section.
enum class DihedralStyleSpec { Cosine };
struct DihedralTypeSpec {
  std::string name;
  DihedralStyleSpec style = DihedralStyleSpec::Cosine;  // the one dihedral law
  double k = 0;
  double theta0_deg = 0;  // theta0 in degrees (0: flat)
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

// [[solid]]: one body of frozen wall particles (the drag is measured per body).
struct SolidSpec {
  std::string name;                          // [[solid]] name (unique; drag output)
  std::string species;                       // [[solid]] species: a frozen species its particles become
  int species_index = -1;                    // resolved by validate()
  std::array<double, 3> velocity{0, 0, 0};   // [[solid]] velocity: wall velocity (Couette)
  ShapeSpec shape;
};

// Velocity rule for a fluid particle moving into the thin layer at a solid surface (seed 000 Sect. 3.2.1).
enum class ReflectionKind { None, Specular, BounceBack, Maxwell };

// [walls]: settings shared by all solids.
struct WallsSpec {
  ReflectionKind reflection = ReflectionKind::BounceBack;  // [walls] reflection
  double layer = 0.1;                                      // [walls] layer: reflecting layer thickness
  double depth = 0.0;                                      // [walls] depth: frozen shell kept (0 = largest cutoff)
  // [walls] equilibrate: steps of the whole box as one periodic fluid (no solids, no body forces) before
  // the particles inside the solids are frozen (seed 000 Sect. 3.2.2); 0 freezes the initial placement.
  std::uint64_t equilibrate = 0;
  std::uint64_t drag_start = 0;                            // [walls] drag_start: steps before drag sampling
  std::uint64_t drag_every = 1;                            // [walls] drag_every
  int drag_blocks = 10;                                    // [walls] drag_blocks: blocks for the error bar
  double reference_length = 0.0;                          // [walls] reference_length: d of Re (0: none)
  double reference_area = 0.0;                             // [walls] reference_area: A of C_D (0: none)
  double viscosity = 0.0;                                  // [walls] viscosity: mu of Re (0: none)
  // Adaptive near-wall force (seed 002 "Boundary Conditions", third category): a force along the surface
  // normal on mobile particles between the reflecting layer and adaptive_range from a solid, from a
  // potential held in adaptive_bins bins of the distance, adjusted every adaptive_every steps until each
  // bin's density equals the bulk's.
  bool adaptive = false;                 // [walls] adaptive
  int adaptive_bins = 10;                // [walls] adaptive_bins
  double adaptive_range = 0.0;           // [walls] adaptive_range (0: the largest cutoff)
  double adaptive_gain = 0.5;            // [walls] adaptive_gain: U_k += gain kT ln(rho_k / rho_bulk) per update
  std::uint64_t adaptive_every = 100;    // [walls] adaptive_every: steps per update (densities sampled every step)
  std::uint64_t adaptive_stop = 0;       // [walls] adaptive_stop: no updates after this step (0: never stop)
};

struct SimulationSpec {
  std::string source;                           // file the spec came from (for messages)
  // The sections of models that declare their own (include/mesodpd/model_section.hpp), by path; only
  // those the file writes. model<T>(path) is the model's values, or null when its section is absent.
  std::map<std::string, std::any, std::less<>> models;
  template <class T>
  const T* model(std::string_view path) const {
    const auto it = models.find(path);
    return it == models.end() ? nullptr : std::any_cast<T>(&it->second);
  }
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
  double max_density = 100.0;                   // [run] max_density: blow-up threshold on the local density (mdpd)
  double max_temperature_ratio = 2.0;           // [run] max_temperature_ratio: a hotter end is a runaway (0: off)
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
  std::vector<DihedralTypeSpec> dihedral_types; // [[dihedral_type]]
  std::vector<MoleculeSpec> molecules;          // [[molecule]]
  BondExclusion bond_exclusion = BondExclusion::None;  // [bonds] exclude
  std::optional<double> bond_reach_set;         // [bonds] reach as written
  int bond_subcycles = 1;                       // [bonds] subcycles: inner steps of the bonded forces per
                                                // time step (multiple time stepping, r-RESPA); 1: none
  double bond_reach = 0;                        // longest bond or angle leg allowed; validate(): default the
                                                // largest pair cutoff. Neighbour cells (and so ghost layers)
                                                // are at least max(cutoff, reach) + skin wide.
  std::vector<SolidSpec> solids;                // [[solid]]
  WallsSpec walls;                              // [walls]
  std::vector<FieldsSpec> fields;               // [analysis.fields] / [[analysis.fields]]
  SurfaceTensionSpec surface_tension;           // [analysis.surface_tension]
  DropletSpec droplet;                          // [analysis.droplet]
  StressProfileSpec stress_profile;             // [analysis.stress_profile]

  // Index into `pairs` for species i, j (either order).
  const PairSpec& pair(int a, int b) const {
    const int i = a < b ? a : b, j = a < b ? b : a;
    const int n = static_cast<int>(species.size());
    return pairs[static_cast<std::size_t>(i * n - i * (i - 1) / 2 + (j - i))];
  }
};

}  // namespace mesodpd
