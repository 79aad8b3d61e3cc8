// Parameter tables of the pair force laws from a validated spec.
#include "engine/pair_laws.hpp"

#include <algorithm>
#include <cmath>

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

// The DPD parameters of a pair with conservative amplitude a, dissipative range rd and interaction range
// `range`.
DpdPairParams dpd_params(const SimulationSpec& spec, const PairSpec& ps, double a, double rd, double range) {
  DpdPairParams q;
  q.a = a;
  q.gamma = ps.gamma;
  q.sigma = std::sqrt(2.0 * ps.gamma * spec.kT);  // seed 000 Eq. 7
  q.rc = ps.rc;
  q.rd = rd;
  q.s = ps.s;
  q.rcut2 = range * range;
  return q;
}
}  // namespace

PairTable<DpdPairParams> make_pair_table(const SimulationSpec& spec) {
  return fill_table<DpdPairParams>(
      spec, [&](const PairSpec& ps) { return dpd_params(spec, ps, ps.a, ps.rd, ps.range(PairStyle::Dpd)); },
      [](const PairSpec& ps) { return ps.range(PairStyle::Dpd); });
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

PairLawTables make_pair_laws(const SimulationSpec& spec) {
  switch (spec.pair_style) {
    case PairStyle::Dpd:
      return LawTable<DpdLaw>{make_pair_table(spec)};
    case PairStyle::Soft:
      return LawTable<SoftLaw>{fill_table<SoftPairParamsT<double>>(spec, [](const PairSpec& ps) {
        return SoftPairParamsT<double>{ps.a, ps.rc, ps.rc * ps.rc};
      }, [](const PairSpec& ps) { return ps.rc; })};
    case PairStyle::Mdpd:
      // seed 000 Eq. 17; the dissipative and random forces act over r_c (as LAMMPS's pair_style mdpd).
      return LawTable<MdpdLaw>{fill_table<MdpdPairParamsT<double>>(spec, [&](const PairSpec& ps) {
        const double range = ps.range(PairStyle::Mdpd);
        return MdpdPairParamsT<double>{ps.a, ps.b, ps.rd, dpd_params(spec, ps, 0.0, ps.rc, range), range * range};
      }, [](const PairSpec& ps) { return ps.range(PairStyle::Mdpd); })};
    case PairStyle::Spline:
      // seed 000 Eqs. 19-23; the dissipative and random forces act over rd.
      return LawTable<SplineLaw>{fill_table<SplinePairParamsT<double>>(spec, [&](const PairSpec& ps) {
        const double range = ps.range(PairStyle::Spline);
        return SplinePairParamsT<double>{ps.a,  ps.repulsion, ps.rc1, ps.attraction, ps.rc2,
                                         dpd_params(spec, ps, 0.0, ps.rd, range), range * range};
      }, [](const PairSpec& ps) { return ps.range(PairStyle::Spline); })};
  }
  return LawTable<DpdLaw>{make_pair_table(spec)};
}

}  // namespace mesodpd
