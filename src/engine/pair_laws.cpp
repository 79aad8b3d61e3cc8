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
}  // namespace

PairTable<DpdPairParams> make_pair_table(const SimulationSpec& spec) {
  return fill_table<DpdPairParams>(spec, [&](const PairSpec& ps) {
    DpdPairParams q;
    q.a = ps.a;
    q.gamma = ps.gamma;
    q.sigma = std::sqrt(2.0 * ps.gamma * spec.kT);  // seed 000 Eq. 7
    q.rc = ps.rc;
    q.rd = ps.rd;
    q.s = ps.s;
    const double range = std::max(ps.rc, ps.rd);
    q.rcut2 = range * range;
    return q;
  }, [](const PairSpec& ps) { return std::max(ps.rc, ps.rd); });
}

PairLawTables make_pair_laws(const SimulationSpec& spec) {
  switch (spec.pair_style) {
    case PairStyle::Dpd:
      return LawTable<DpdLaw>{make_pair_table(spec)};
    case PairStyle::Soft:
      return LawTable<SoftLaw>{fill_table<SoftPairParamsT<double>>(spec, [](const PairSpec& ps) {
        return SoftPairParamsT<double>{ps.a, ps.rc, ps.rc * ps.rc};
      }, [](const PairSpec& ps) { return ps.rc; })};
  }
  return LawTable<DpdLaw>{make_pair_table(spec)};
}

}  // namespace mesodpd
