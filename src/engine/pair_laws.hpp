// The compile-time list of pair force laws the engine can run, and their parameter tables built from a
// spec. Adding a law: its header in src/physics/ (the force and what it declares about its keys,
// physics/law_keys.hpp) and one entry in PairLawTables (docs/architecture.md, "Add a pair force law").
#pragma once
#include <cstring>
#include <optional>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"
#include "physics/density_kernel.hpp"
#include "physics/law_keys.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/edpd_pair.hpp"
#include "physics/tdpd_pair.hpp"
#include "physics/mdpd_pair.hpp"
#include "physics/sdpd_pair.hpp"
#include "physics/spdpd_pair.hpp"
#include "physics/pair_table.hpp"
#include "physics/soft_pair.hpp"
#include "physics/spline_pair.hpp"

namespace mesodpd {

// Arithmetic type of the pair passes: double, or float with -DMESODPD_SINGLE=ON. Positions,
// velocities and the fixed-point sums stay double/integer either way (docs/performance.md).
#ifdef MESODPD_SINGLE_PRECISION
using PairReal = float;
#else
using PairReal = double;
#endif

// The number of species the pair loop has to tell apart in a parameter table: 1 when every species pair
// has the same parameters (say, frozen wall particles that take the fluid's [pair] values), so that the
// loop runs with the parameters as constants instead of looking them up pair by pair; otherwise the
// table's species count. The same values either way, so the same bits.
template <class Params>
int distinct_species(const std::vector<Params>& params, int n_species) {
  for (const auto& q : params)
    if (std::memcmp(&q, params.data(), sizeof(Params)) != 0) return n_species;
  return 1;
}

// One law with its per-species-pair parameters: `table` in double (reference loop, analysis) and
// `params_real`, the same in the pair arithmetic type, converted once on construction (not per step);
// `loop_species`: distinct_species of params_real.
template <class Law>
struct LawTable {
  using LawType = Law;
  PairTable<typename Law::template Params<double>> table;
  std::vector<typename Law::template Params<PairReal>> params_real;
  int loop_species = 1;

  LawTable() = default;
  explicit LawTable(PairTable<typename Law::template Params<double>> t) : table(std::move(t)) {
    for (const auto& q : table.params) params_real.push_back(q.template as<PairReal>());
    loop_species = distinct_species(params_real, table.n_species);
  }
};

// A build may append laws of its own to the list: `#define MESODPD_EXTRA_PAIR_LAWS , LawTable<MyLaw>` in a
// header force-included into every file of the engine, the schema and the api (the tests do, to prove
// the recipe "add a pair force law" with a law that lives outside src/: tests/modules/).
#ifndef MESODPD_EXTRA_PAIR_LAWS
#define MESODPD_EXTRA_PAIR_LAWS
#endif

// Every law the shared pair loop is instantiated for (per SIMD target), in the order of PairStyle: the
// one list of pair laws. The schema takes the style names and keys from it. A law appended here needs
// no enumerator in PairStyle: the index is its style.
using PairLawTables =
    std::variant<LawTable<DpdLaw>, LawTable<SoftLaw>, LawTable<MdpdLaw>, LawTable<SplineLaw>,
                 LawTable<EdpdLaw>, LawTable<TdpdLaw>, LawTable<SdpdLaw>,
                 LawTable<SpdpdLaw> MESODPD_EXTRA_PAIR_LAWS>;
inline constexpr std::size_t kPairLawCount = std::variant_size_v<PairLawTables>;

// What one law of the list declares (physics/law_keys.hpp), without its type: for the schema.
struct PairLawInfo {
  std::string_view style, doc;
  std::vector<std::string_view> shared;                   // the shared keys it reads
  std::vector<std::pair<std::string_view, std::string_view>> required;  // shared keys it requires, with hints
  std::vector<LawKey> own;
  std::vector<LawKey> species_own;                        // its [[species]] keys (kSpeciesOwn)
  double min_a = 0;                                       // the lowest a allowed
  bool noise = true, density = false;                     // kNoise, kDensity
  int scalars = 0;                                        // kScalars (per-particle transported scalars)
  std::vector<std::string_view> scalar_fields, scalar_rates;  // their particle fields (kScalarFields, kScalarRates)
  double (*range)(const PairValues&) = nullptr;
  LawProblem (*problem)(const PairValues&) = nullptr;
  LawProblem (*warning)(const PairValues&) = nullptr;  // law_warning
  DensityKernelKind default_kernel = DensityKernelKind::Warren;  // law_default_kernel (kDensity)
  double (*density_range)(const PairValues&) = nullptr;          // law_density_range (kDensity)
  std::vector<DensityKernelKind> kernels;                        // law_kernels (kDensity)
};
// The laws of PairLawTables in order (index = PairStyle).
const std::vector<PairLawInfo>& pair_law_infos();
inline const PairLawInfo& pair_law(PairStyle style) { return pair_law_infos().at(static_cast<std::size_t>(style)); }

// A resolved species pair of a validated spec as the spec's law reads it (its own keys in the order it
// declares them; sigma = sqrt(2 gamma kT), seed 000 Eq. 7), with the masses and species keys of the
// table entry's species i and j (by default ps.i and ps.j; the entry (b, a) of a pair a < b has them
// the other way round).
PairValues pair_values(const PairSpec& ps, const SimulationSpec& spec, int species_i = -1, int species_j = -1);
// The distance beyond which the pair does not interact under `style`.
double pair_range(const PairSpec& ps, PairStyle style);

// The rows of the [pair] and [[pair.override]] key tables of docs/config.md: the style, the shared keys,
// every law's own keys (each marked with the styles that read it), kernel and mixing.
std::vector<keys::KeyDoc> pair_key_docs();
// The rows of the laws' [[species]] keys (each marked with the styles that read it).
std::vector<keys::KeyDoc> pair_species_key_docs();
std::vector<keys::KeyDoc> pair_override_key_docs();

// A density kernel and its per-species-pair range, for ForceCompute::compute_density.
struct DensitySettings {
  DensityKernelKind kernel = DensityKernelKind::Warren;
  PairTable<DensityParamsT<double>> table;
};

// The law and parameter table of a validated spec (sigma from the fluctuation-dissipation relation).
PairLawTables make_pair_laws(const SimulationSpec& spec);
// The density pass a spec's law needs before its force pass (a law with kDensity: the kernel of
// pair.kernel, or the law's default, over each pair's density range; many-body DPD: r_d), or nothing.
std::optional<DensitySettings> make_density_settings(const SimulationSpec& spec);
// The density kernel a spec's run uses (pair.kernel, else its law's default).
DensityKernelKind density_kernel_of(const SimulationSpec& spec);
// The DPD table of a spec (the conservative part also serves the g(r) pressure integral).
PairTable<DpdPairParams> make_pair_table(const SimulationSpec& spec);

inline double max_cutoff(const PairLawTables& laws) {
  return std::visit([](const auto& t) { return t.table.max_cutoff; }, laws);
}

}  // namespace mesodpd
