// Parameter tables of the pair force laws from a validated spec.
#include "engine/pair_laws.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "engine/transported_scalars.hpp"

namespace mesodpd {

namespace {
// Fills a dense table from the spec's resolved species pairs with `make(pair)`, or `make(pair, a, b)`
// where the entry's species order matters (a law's species values: entry (a, b) has species a as i);
// `range(pair)` is the pair's interaction range.
template <class Params, class Make, class Range>
PairTable<Params> fill_table(const SimulationSpec& spec, Make&& make, Range&& range) {
  PairTable<Params> t;
  t.n_species = static_cast<int>(spec.species.size());
  t.params.resize(static_cast<std::size_t>(t.n_species * t.n_species));
  for (int a = 0; a < t.n_species; ++a)
    for (int b = 0; b < t.n_species; ++b) {
      Params q;
      if constexpr (std::is_invocable_v<Make, const PairSpec&, int, int>)
        q = make(spec.pair(a, b), a, b);
      else
        q = make(spec.pair(a, b));
      t.params[static_cast<std::size_t>(a * t.n_species + b)] = q;
      t.max_cutoff = std::max(t.max_cutoff, range(spec.pair(a, b)));
    }
  return t;
}

// The info of law I of the list, and of all from I on.
template <std::size_t I>
void add_infos(std::vector<PairLawInfo>& out) {
  if constexpr (I < kPairLawCount) {
    using Law = typename std::variant_alternative_t<I, PairLawTables>::LawType;
    PairLawInfo info;
    info.style = Law::kStyle;
    info.doc = Law::kDoc;
    info.shared.assign(Law::kShared.begin(), Law::kShared.end());
    for (std::size_t k = 0; k < Law::kRequired.size(); ++k) {
      if constexpr (requires { Law::kRequiredHints; })
        info.required.emplace_back(Law::kRequired[k], Law::kRequiredHints[k]);
      else
        info.required.emplace_back(Law::kRequired[k], std::string_view{});
    }
    info.own.assign(Law::kOwn.begin(), Law::kOwn.end());
    static_assert(Law::kOwn.size() <= PairValues::kMaxOwn, "more own keys than PairValues holds");
    constexpr auto species_keys = law_species_keys<Law>();
    static_assert(species_keys.size() <= PairValues::kMaxSpeciesOwn, "more species keys than PairValues holds");
    info.species_own.assign(species_keys.begin(), species_keys.end());
    info.scalars = law_scalars<Law>;
    if constexpr (law_scalars<Law> > 0) {
      static_assert(Law::kScalarFields.size() == law_scalars<Law> && Law::kScalarRates.size() == law_scalars<Law>);
      info.scalar_fields.assign(Law::kScalarFields.begin(), Law::kScalarFields.end());
      info.scalar_rates.assign(Law::kScalarRates.begin(), Law::kScalarRates.end());
    }
    info.min_a = Law::kMinA;
    info.noise = Law::kNoise || law_noise_words<Law> > 0;  // has a random force
    info.density = Law::kDensity;
    info.range = &Law::range;
    info.problem = &Law::problem;
    info.warning = &law_warning<Law>;
    info.default_kernel = law_default_kernel<Law>;
    info.density_range = &law_density_range<Law>;
    constexpr auto kernels = law_kernels<Law>();
    info.kernels.assign(kernels.begin(), kernels.end());
    out.push_back(std::move(info));
    add_infos<I + 1>(out);
  }
}

// The table of law I for a spec whose style is I (or of any other index, for no law).
template <std::size_t I>
PairLawTables make_law_tables(const SimulationSpec& spec) {
  if constexpr (I < kPairLawCount) {
    if (static_cast<std::size_t>(spec.pair_style) == I) {
      using Law = typename std::variant_alternative_t<I, PairLawTables>::LawType;
      return LawTable<Law>{fill_table<typename Law::template Params<double>>(
          spec, [&](const PairSpec& ps, int a, int b) { return Law::make(pair_values(ps, spec, a, b)); },
          [&](const PairSpec& ps) { return pair_range(ps, spec.pair_style); })};
    }
    return make_law_tables<I + 1>(spec);
  } else {
    throw std::invalid_argument("pair.style: no pair law with this index");
  }
}
}  // namespace

const std::vector<PairLawInfo>& pair_law_infos() {
  static const std::vector<PairLawInfo> infos = [] {
    std::vector<PairLawInfo> out;
    add_infos<0>(out);
    return out;
  }();
  return infos;
}

namespace {
PairValues values_of(const PairSpec& ps, PairStyle style, double kT) {
  PairValues v;
  v.a = ps.a;
  v.gamma = ps.gamma;
  v.sigma = std::sqrt(2.0 * ps.gamma * kT);  // seed 000 Eq. 7
  v.rc = ps.rc;
  v.rd = ps.rd;
  v.s = ps.s;
  const PairLawInfo& law = pair_law(style);
  for (std::size_t k = 0; k < law.own.size(); ++k) v.own[k] = ps.value(law.own[k].name);
  v.kT = kT;
  return v;
}
}  // namespace

DensityKernelKind density_kernel_of(const SimulationSpec& spec) {
  if (!spec.pair_section.kernel) return pair_law(spec.pair_style).default_kernel;
  switch (*spec.pair_section.kernel) {
    case DensityKernelChoice::Lucy: return DensityKernelKind::Lucy;
    case DensityKernelChoice::Wendland: return DensityKernelKind::Wendland;
    case DensityKernelChoice::Warren: break;
  }
  return DensityKernelKind::Warren;
}

PairValues pair_values(const PairSpec& ps, const SimulationSpec& spec, int species_i, int species_j) {
  PairValues v = values_of(ps, spec.pair_style, spec.kT);
  const PairLawInfo& law = pair_law(spec.pair_style);
  v.kernel = density_kernel_of(spec);
  v.dt = spec.dt;
  v.number_density = mobile_density(spec);
  const auto n = static_cast<int>(spec.species.size());
  const int a = species_i >= 0 ? species_i : ps.i, b = species_j >= 0 ? species_j : ps.j;
  if (a < n && b < n) {
    const SpeciesSpec& si = spec.species[static_cast<std::size_t>(a)];
    const SpeciesSpec& sj = spec.species[static_cast<std::size_t>(b)];
    v.mass_i = si.mass;
    v.mass_j = sj.mass;
    v.frozen_i = si.frozen;
    v.frozen_j = sj.frozen;
    for (std::size_t k = 0; k < law.species_own.size(); ++k) {
      const auto of = [&](const SpeciesSpec& sp) {
        const auto it = sp.own.find(law.species_own[k].name);
        return it == sp.own.end() ? law.species_own[k].fallback : it->second;
      };
      v.species_i[k] = of(si);
      v.species_j[k] = of(sj);
    }
  }
  return v;
}

// The range reads none of the species values.
double pair_range(const PairSpec& ps, PairStyle style) { return pair_law(style).range(values_of(ps, style, 1.0)); }

namespace {
// `"dpd"`, `"soft"`: styles whose law passes `pred`.
template <class Pred>
std::string styles_where(Pred&& pred) {
  std::string out;
  for (const PairLawInfo& law : pair_law_infos())
    if (pred(law)) out += std::string(out.empty() ? "" : ", ") + "`" + std::string(law.style) + "`";
  return out;
}

// The row of a law key of the list `which` (the [pair] keys or the [[species]] keys), marked with the
// styles that declare it.
keys::KeyDoc own_row(const LawKey& k, std::vector<LawKey> PairLawInfo::*which = &PairLawInfo::own) {
  const std::string users = styles_where([&](const PairLawInfo& law) {
    const std::vector<LawKey>& list = law.*which;
    return std::any_of(list.begin(), list.end(), [&](const LawKey& o) { return o.name == k.name; });
  });
  const keys::Range r{k.lo, k.hi, k.lo_closed, k.hi_closed};
  return {std::string(k.name), "number", k.required ? "none" : keys::doc_number(k.fallback), r.doc(),
          users + " only: " + std::string(k.doc)};
}
}  // namespace

std::vector<keys::KeyDoc> pair_key_docs() {
  std::vector<keys::KeyDoc> rows;
  std::string style_doc = "The pair force law.", styles;
  for (const PairLawInfo& law : pair_law_infos()) {
    style_doc += " `" + std::string(law.style) + "`: " + std::string(law.doc);
    styles += std::string(styles.empty() ? "" : ", ") + "`\"" + std::string(law.style) + "\"`";
  }
  rows.push_back({"style", "string", "`\"" + std::string(pair_law_infos().front().style) + "\"`", styles, style_doc});
  const std::string negative_a = styles_where([](const PairLawInfo& law) { return law.min_a < 0; });
  rows.push_back({"a", "number", "25.0", ">= 0 (any with " + negative_a + ")",
                  "Conservative repulsion a_ij, F^C = a_ij (1 - r/r_c) r-hat (seed 000 Eq. 3). Refused with `mixing = "
                  "\"geometric\"`."});
  rows.push_back({"gamma", "number", "4.5", ">= 0",
                  "Dissipative strength gamma (seed 000 Eq. 4). The random strength follows from it: sigma = sqrt(2 "
                  "gamma kT)."});
  rows.push_back({"sigma", "number", "none", ">= 0",
                  "Optional cross-check only: if given, sigma^2 must equal 2 gamma kT within a relative 1e-6 (seed 000 "
                  "Eq. 7), else an error naming `pair.sigma` states the consistent value. gamma stays the independent "
                  "parameter."});
  rows.push_back({"rc", "number", "1.0", "(0, 10]", "Cutoff of the conservative force."});
  rows.push_back({"rd", "number", "= `rc`", "(0, 10]",
                  "Cutoff of the dissipative and random forces (seed 000 Eq. 8). When not set, each pair's rd equals "
                  "that pair's rc (also an overridden rc)."});
  rows.push_back({"s", "number", "2.0", "(0, 10]",
                  "Exponent of the weight function w^D = (w^R)^2 = (1 - r/r_d)^s (seed 000 Eq. 8); s = 2 is standard "
                  "DPD, smaller s raises the viscosity."});
  std::vector<std::string_view> seen;
  for (const PairLawInfo& law : pair_law_infos())
    for (const LawKey& k : law.own)
      if (std::find(seen.begin(), seen.end(), k.name) == seen.end()) {
        seen.push_back(k.name);
        rows.push_back(own_row(k));
      }
  const std::string density = styles_where([](const PairLawInfo& law) { return law.density; });
  std::string kernel_default;
  for (const PairLawInfo& law : pair_law_infos())
    if (law.density)
      kernel_default += fmt::format("{}`\"{}\"` ({})", kernel_default.empty() ? "" : ", ",
                                    density_kernel_name(law.default_kernel), law.style);
  rows.push_back({"kernel", "string", kernel_default, "`\"warren\"`, `\"lucy\"`, `\"wendland\"`",
                  density + " only: the local-density kernel, Warren's 15/(2 pi r_d^3)(1 - r/r_d)^2, Lucy's 105/(16 pi "
                            "r_d^3)(1 + 3r/r_d)(1 - r/r_d)^3 (LAMMPS `mdpd/rhosum`) or Wendland's C2 21/(2 pi r_d^3)(1 - "
                            "r/r_d)^4(1 + 4r/r_d). One kernel for all pairs, each pair with its own range (`mdpd`: r_d)."});
  rows.push_back({"mixing", "string", "`\"explicit\"`", "`\"explicit\"`, `\"geometric\"`",
                  "How a_ij is formed: `explicit` uses `pair.a` for every pair; `geometric` uses a_ij = sqrt(a_i a_j) "
                  "from `species[].a` (seed 002 Eq. 4). With `explicit`, `species[].a` is refused."});
  return rows;
}

std::vector<keys::KeyDoc> pair_species_key_docs() {
  std::vector<keys::KeyDoc> rows;
  std::vector<std::string_view> seen;
  for (const PairLawInfo& law : pair_law_infos())
    for (const LawKey& k : law.species_own)
      if (std::find(seen.begin(), seen.end(), k.name) == seen.end()) {
        seen.push_back(k.name);
        rows.push_back(own_row(k, &PairLawInfo::species_own));
      }
  return rows;
}

std::vector<keys::KeyDoc> pair_override_key_docs() {
  std::vector<keys::KeyDoc> rows;
  rows.push_back({"species", "array of 2 strings", "required", "defined species names",
                  "Names of the pair (`[\"A\", \"B\"]` = `[\"B\", \"A\"]`; may be equal, `[\"A\", \"A\"]`). Each "
                  "must be a defined species; a pair may be overridden only once."});
  for (const keys::KeyDoc& r : pair_key_docs())
    if (r.name != "style" && r.name != "kernel" && r.name != "mixing")
      rows.push_back({r.name, r.type, "from `[pair]`", r.allowed, "As in `[pair]`."});
  return rows;
}

PairTable<DpdPairParams> make_pair_table(const SimulationSpec& spec) {
  return fill_table<DpdPairParams>(
      spec, [&](const PairSpec& ps) { return DpdLaw::make(values_of(ps, PairStyle::Dpd, spec.kT)); },
      [](const PairSpec& ps) { return pair_range(ps, PairStyle::Dpd); });
}

std::optional<DensitySettings> make_density_settings(const SimulationSpec& spec) {
  const PairLawInfo& law = pair_law(spec.pair_style);
  if (!law.density) return std::nullopt;
  DensitySettings ds;
  ds.kernel = density_kernel_of(spec);
  const auto range = [&](const PairSpec& ps) { return law.density_range(pair_values(ps, spec)); };
  ds.table = fill_table<DensityParamsT<double>>(
      spec, [&](const PairSpec& ps) { const double r = range(ps); return DensityParamsT<double>{r, r * r}; }, range);
  return ds;
}

PairLawTables make_pair_laws(const SimulationSpec& spec) { return make_law_tables<0>(spec); }

}  // namespace mesodpd
