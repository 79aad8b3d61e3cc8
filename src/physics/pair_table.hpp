// Dense species-by-species table of DPD pair parameters, read by the force loops.
#pragma once
#include <vector>

#include "physics/dpd_pair.hpp"

namespace mesodpd {

struct PairTable {
  int n_species = 0;
  std::vector<DpdPairParams> params;  // n_species * n_species, symmetric
  double max_cutoff = 0.0;

  const DpdPairParams& operator()(int a, int b) const {
    return params[static_cast<std::size_t>(a * n_species + b)];
  }
};

}  // namespace mesodpd
