// The serial reference backend: every pair of local particles by brute force (minimum image, O(N^2)),
// evaluated with the same force-law functors and density kernels as the fast loop, in double precision.
// Plain and readable on purpose: it is the oracle the fast pair loop is tested against (DESIGN.md).
// The functions that analyses call during a run (local virials, virial terms, densities) find the
// same pairs through cells instead, in the same order, so they cost O(N) and give the same bits.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/box.hpp"
#include "core/pair_sums.hpp"
#include "core/particle_data.hpp"
#include "engine/force_compute.hpp"

namespace mesodpd {

// Calls visit(i, j, dx, dy, dz, r) for every pair i < j of local particles closer than `cutoff` (minimum
// image on periodic axes), i ascending, then j ascending, with d = r_i - r_j: by trying every pair, or
// with `binned` through cells (the same sequence, O(N)). For tests of the two.
void reference_pairs(const ParticleData& p, const Box& box, double cutoff, bool binned,
                     const std::function<void(std::size_t, std::size_t, double, double, double, double)>& visit);

// Pair forces on the local particles of `p` (a single domain, no ghosts) at step `step`: writes f[i]
// and the pair sums. Sums are accumulated per pair in the engine's fixed point, so in the double build
// the fast loop must agree bit for bit. `rho` (one entry per particle) for laws with kDensity. For a law
// with scalars (kScalars; its fields enabled), `rate` (if given) receives their rates, scalar c of
// particle i at c * n_local + i.
void reference_forces(const ParticleData& p, const Box& box, const PairLawTables& laws, NoiseSettings noise,
                      std::uint64_t step, double dt, std::vector<std::array<double, 3>>& f, PairSums& sums,
                      const double* rho = nullptr, std::vector<double>* rate = nullptr);

// w[i] = (1/2) sum over j != i of r_ij . F^C_ij (conservative forces only; seed 000 Eq. 24), half of each
// pair's virial to each of its particles: the per-particle virial behind the local pressures of
// [analysis.droplet]. `rho` for laws with kDensity. Plain double sums, in index order.
void reference_conservative_virial(const ParticleData& p, const Box& box, const PairLawTables& laws,
                                   std::vector<double>& w, const double* rho = nullptr);

// Whether the pair force between two particles (by global id) is excluded (bonds.exclude).
using ExcludedPair = std::function<bool(std::uint32_t, std::uint32_t)>;

// Appends one VirialTerm (core/pair_sums.hpp) per pair with a nonzero conservative force, leaving out
// the pairs `excluded` names: the configurational part of the pressure tensor, pair by pair, for
// [analysis.stress_profile]. Serial, pairs in index order.
void reference_conservative_virial_terms(const ParticleData& p, const Box& box, const PairLawTables& laws,
                                         VirialTerms& terms, const double* rho = nullptr,
                                         const ExcludedPair& excluded = {});

// The per-particle conservative virial of a set of particles with these laws (and, for laws with
// kDensity, local densities recomputed over the set): the callback of [analysis.droplet]
// (analysis/droplet.hpp, LocalVirial), serial and in index order.
std::function<void(const ParticleData&, const Box&, std::vector<double>&)> make_local_virial(
    PairLawTables laws, std::optional<DensitySettings> density);

// The noise-free exchange of a transported scalar (a law with kScalars; eDPD's heat, tDPD's solutes)
// between pairs of local particles: for every pair i < j within the law's range that `want(i, j, dx,
// dy, dz)` accepts (d = r_i - r_j), visit(i, j, q) with q the amount of scalar `channel` per unit time
// that flows from j into i, in conserved units (capacity[species] x the rate: C_v T for heat, C for a
// solute). The pair's random terms are set to zero (their mean), so q is the conduction (Fick) part:
// between two mobile particles the antisymmetric half (cap_i q_i - cap_j q_j) / 2, which leaves out a
// symmetric source such as eDPD's viscous heating; with a wall (frozen) particle the wall's side alone,
// which holds no viscous share. For [analysis.flux]; serial, pairs in index order. Throws
// std::invalid_argument for a law without scalars or a channel the particles do not hold.
void reference_scalar_exchange(const ParticleData& p, const Box& box, const PairLawTables& laws, int channel,
                               const std::vector<double>& capacity,
                               const std::function<bool(std::size_t, std::size_t, double, double, double)>& want,
                               const std::function<void(std::size_t, std::size_t, double)>& visit);

// rho[i] = sum over j != i of w(r_ij), in the engine's fixed point.
void reference_density(const ParticleData& p, const Box& box, const DensitySettings& density, std::vector<double>& rho);

}  // namespace mesodpd
