// Dense species-by-species table of pair parameters of one force law (or density kernel), read by the
// pair loops.
#pragma once
#include <cstddef>
#include <vector>

namespace mesodpd {

template <class Params>
struct PairTable {
  int n_species = 0;
  std::vector<Params> params;  // n_species * n_species, symmetric
  double max_cutoff = 0.0;     // largest interaction range of any pair

  const Params& operator()(int a, int b) const { return params[static_cast<std::size_t>(a * n_species + b)]; }
};

}  // namespace mesodpd
