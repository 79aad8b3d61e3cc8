// Parameter tables of the pair force laws from a validated spec.
#include "engine/pair_laws.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mesodpd {

namespace {
// Fills a dense table from the spec's resolved species pairs with `make(pair)`; `range(pair)` is the
// pair's interaction range.
template <class Params, class Make, class Range>
PairTable<Params> fill_table(const SimulationSpec& spec, Make&& make, Range&& range) {
  PairTable<Params> t;
  t.n_species = static_cast<int>(spec.species.size());
  t.params.resize(static_cast<std::size_t>(t.n_species * t.n_species));
  for (int a = 0; a < t.n_species; ++a)
    for (int b = 0; b < t.n_species; ++b) {
      const Params q = make(spec.pair(a, b));
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
    info.min_a = Law::kMinA;
    info.noise = Law::kNoise;
    info.density = Law::kDensity;
    info.range = &Law::range;
    info.problem = &Law::problem;
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
          spec, [&](const PairSpec& ps) { return Law::make(pair_values(ps, spec.pair_style, spec.kT)); },
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

PairValues pair_values(const PairSpec& ps, PairStyle style, double kT) {
  PairValues v;
  v.a = ps.a;
  v.gamma = ps.gamma;
  v.sigma = std::sqrt(2.0 * ps.gamma * kT);  // seed 000 Eq. 7
  v.rc = ps.rc;
  v.rd = ps.rd;
  v.s = ps.s;
  const PairLawInfo& law = pair_law(style);
  for (std::size_t k = 0; k < law.own.size(); ++k) v.own[k] = ps.value(law.own[k].name);
  return v;
}

double pair_range(const PairSpec& ps, PairStyle style) { return pair_law(style).range(pair_values(ps, style, 1.0)); }

PairTable<DpdPairParams> make_pair_table(const SimulationSpec& spec) {
  return fill_table<DpdPairParams>(
      spec, [&](const PairSpec& ps) { return DpdLaw::make(pair_values(ps, PairStyle::Dpd, spec.kT)); },
      [](const PairSpec& ps) { return pair_range(ps, PairStyle::Dpd); });
}

std::optional<DensitySettings> make_density_settings(const SimulationSpec& spec) {
  if (spec.pair_style != PairStyle::Mdpd) return std::nullopt;
  DensitySettings ds;
  ds.kernel = spec.pair_section.kernel.value_or(DensityKernelChoice::Warren) == DensityKernelChoice::Lucy
                  ? DensityKernelKind::Lucy
                  : DensityKernelKind::Warren;
  ds.table = fill_table<DensityParamsT<double>>(
      spec, [](const PairSpec& ps) { return DensityParamsT<double>{ps.rd, ps.rd * ps.rd}; },
      [](const PairSpec& ps) { return ps.rd; });
  return ds;
}

PairLawTables make_pair_laws(const SimulationSpec& spec) { return make_law_tables<0>(spec); }

}  // namespace mesodpd
