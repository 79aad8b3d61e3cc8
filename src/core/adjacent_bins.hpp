// The bins next to a bin along one axis of a grid, for the small searches that bin particles themselves
// (the reference pair loop, the pairwise thermostats' sweep, the membranes' cell-cell repulsion).
#pragma once
#include <algorithm>

namespace mesodpd {

// The distinct bins c - 1, c, c + 1 along an axis of n bins: wrapped round on a periodic axis, cut at the
// ends of a bounded one, and each listed once (an axis of one or two bins meets a neighbour twice through
// the wrap). Writes them to `out` in that order and returns how many; `wrapped[k]`, where given, says
// whether out[k] was reached through the periodic wrap.
inline int adjacent_bins(int c, int n, bool periodic, int out[3], bool wrapped[3] = nullptr) {
  int count = 0;
  for (int o = -1; o <= 1; ++o) {
    int k = c + o;
    bool w = false;
    if (k < 0 || k >= n) {
      if (!periodic) continue;
      k = (k + n) % n;
      w = true;
    }
    if (std::find(out, out + count, k) != out + count) continue;
    if (wrapped) wrapped[count] = w;
    out[count++] = k;
  }
  return count;
}

}  // namespace mesodpd
