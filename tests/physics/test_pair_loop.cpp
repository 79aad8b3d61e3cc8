// The shared pair loop against the serial reference loop (engine/reference_pair_loop.hpp): every force
// law of the compile-time list and both density kernels, on random configurations with several species,
// for 1-3 threads, both neighbour methods and every SIMD instruction set this CPU runs. In the double
// build the fast loop must agree bit for bit; in the single-precision build to float rounding.
#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <omp.h>

#include <array>
#include <cstdio>
#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "engine/force_compute.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "neighbor/neighbor_list.hpp"
#include "energy_drift.hpp"
#include "random_particles.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {

#ifdef MESODPD_SINGLE_PRECISION
constexpr bool kExact = false;
#else
constexpr bool kExact = true;
#endif

// n particles of `species` kinds, uniformly placed, Gaussian velocities, sparse ids. The last two
// particles sit on top of each other (a pair at r = 0 must give zero force, not NaN).
ParticleData random_particles(const Box& box, std::size_t n, int species, std::uint64_t seed) {
  ParticleData p = test::random_particles(box, n, seed, species, 7, 5);
  p.x[n - 1] = p.x[n - 2];
  p.y[n - 1] = p.y[n - 2];
  p.z[n - 1] = p.z[n - 2];
  return p;
}

// The style of the law named `name` (laws appended to the list have no PairStyle enumerator).
PairStyle style_named(std::string_view name) {
  const std::vector<PairLawInfo>& infos = pair_law_infos();
  for (std::size_t k = 0; k < infos.size(); ++k)
    if (infos[k].style == name) return static_cast<PairStyle>(k);
  throw std::invalid_argument("no pair law named " + std::string(name));
}

// Three species with different parameters for every pair (cutoffs 0.8 to 1.2).
SimulationSpec three_species(PairStyle style, double s) {
  SimulationSpec spec;
  spec.kT = 1.3;
  spec.pair_style = style;
  for (const char* name : {"A", "B", "C"}) {
    SpeciesSpec sp;
    sp.name = name;
    spec.species.push_back(sp);
  }
  // Unordered pairs in the spec's order: (0,0) (0,1) (0,2) (1,1) (1,2) (2,2).
  const double a[6] = {25, 40, 31, 25, 18, 60};
  const double rc[6] = {1.0, 1.1, 0.9, 1.2, 1.0, 0.8};
  const double rd[6] = {1.0, 0.95, 1.15, 1.2, 0.8, 1.0};
  for (int k = 0; k < 6; ++k) {
    PairSpec ps;
    ps.a = a[k];
    ps.gamma = 3.0 + k;
    ps.rc = rc[k];
    ps.rd = rd[k];
    ps.s = s;
    if (style == PairStyle::Mdpd) {
      // Warren-like: attraction A < 0, many-body repulsion B > 0 over r_d < r_c, all different per pair.
      ps.a = -a[k];
      ps.own["b"] = 10.0 + 3 * k;
      ps.rd = 0.55 + 0.05 * k;
    }
    if (style == PairStyle::Spline) {
      // Liu's shape with per-pair coefficients and ranges (seed 000 Eq. 19).
      ps.a = 18.75 - k;
      ps.own["repulsion"] = 2.0 + 0.1 * k;
      ps.own["rc1"] = 0.8 - 0.02 * k;
      ps.own["attraction"] = 0.9 + 0.05 * k;
      ps.own["rc2"] = rc[k];
    }
    if (pair_law(style).style == "edpd") {
      // eDPD: conduction over its own cutoff (the pair's rc for one pair), a temperature-dependent
      // amplitude for some pairs; species with different heat capacities and masses.
      ps.own["kappa"] = 2e-3 * (k + 1);
      ps.own["rct"] = k == 2 ? 0.0 : 0.85 + 0.05 * k;
      ps.own["st"] = k == 4 ? 1.5 : 2.0;
      ps.own["a_t"] = k % 2 == 0 ? 1.0 : 0.0;
      ps.own["kappa_t1"] = 0.1 * k;
      ps.own["kappa_t2"] = -0.05;
    }
    if (pair_law(style).style == "tdpd") {
      // tDPD: two solutes with their own kappa and random flux over a solute cutoff of their own.
      ps.own["rcc"] = k == 3 ? 0.0 : 0.9 + 0.07 * k;
      ps.own["kappa1"] = 0.5 + 0.2 * k;
      ps.own["kappa2"] = 2.0 - 0.1 * k;
      ps.own["epsilon1"] = 0.05 * k;
      ps.own["epsilon2"] = 0.1;
      for (const char* sc : {"sc1", "sc2", "sc3", "sc4"}) ps.own[sc] = 2.0;
    }
    spec.pairs.push_back(ps);
  }
  if (pair_law(style).style == "sdpd")
    for (std::size_t k = 0; k < spec.pairs.size(); ++k) {
      // Smoothed DPD: every pair with its own viscosities, sound speed, reference density, background
      // pressure and kernel cutoff (rc above); species of different masses (below).
      PairSpec& ps = spec.pairs[k];
      const double kd = static_cast<double>(k);
      ps.own["eta"] = 0.5 + 0.3 * kd;
      ps.own["zeta"] = 0.1 * kd;
      ps.own["c"] = 3.0 + kd;
      ps.own["rho0"] = 2.5 + 0.2 * kd;
      ps.own["p_b"] = 0.5 * kd;
      ps.own["eos_exponent"] = 1.0;
      // One pair that does not interact (pair (1, 2)): no density contribution and no force either way.
      ps.own["interact"] = k == 4 ? 0.0 : 1.0;
    }
  if (pair_law(style).style == "spdpd")
    for (std::size_t k = 0; k < spec.pairs.size(); ++k) {
      // Single-particle DPD: a friction across e of its own per pair, one pair with its own exponent;
      // species of different radii, masses and (one) an explicit moment of inertia (below).
      spec.pairs[k].own["gamma_perp"] = 1.5 + 0.7 * static_cast<double>(k);
      spec.pairs[k].own["s_perp"] = 0.0;
    }
  if (pair_law(style).style == "edpd" || pair_law(style).style == "sdpd" || pair_law(style).style == "spdpd")
    for (std::size_t k = 0; k < spec.species.size(); ++k) {
      if (pair_law(style).style == "spdpd") {
        spec.species[k].own["radius"] = 0.3 + 0.2 * static_cast<double>(k);
        spec.species[k].own["inertia"] = k == 2 ? 0.35 : 0.0;
      }
      if (pair_law(style).style == "edpd") {
        spec.species[k].own["cv"] = 100.0 + 50.0 * static_cast<double>(k);
        spec.species[k].own["temperature"] = 0.0;
      }
      spec.species[k].mass = 1.0 + 0.25 * static_cast<double>(k);
    }
  return spec;
}

// eDPD with s_T = 2 for every pair (three_species gives one pair 1.5), so that its evaluator takes no
// power for the heat weight and none for a_t (0 or 1): EdpdLaw's plain evaluators; three_species
// itself takes the one with every power general.
SimulationSpec edpd_plain(double s) {
  SimulationSpec spec = three_species(style_named("edpd"), s);
  for (PairSpec& ps : spec.pairs) ps.own["st"] = 2.0;
  return spec;
}

// eDPD with a temperature-dependent exponent s(T) (the general pow form for every pair), plain (s_T = 2,
// a_t 0 or 1) or with a power for a_t = 0.7 on one pair.
SimulationSpec edpd_with_s_of_t(bool powers) {
  SimulationSpec spec = edpd_plain(2.0);
  for (PairSpec& ps : spec.pairs) {
    ps.own["s_t1"] = 0.3;
    ps.own["s_t3"] = -0.1;
  }
  if (powers) spec.pairs[1].own["a_t"] = 0.7;
  return spec;
}

// tDPD with solute exponents other than 2 (the general pow form).
SimulationSpec tdpd_general() {
  SimulationSpec spec = three_species(style_named("tdpd"), 2.0);
  for (PairSpec& ps : spec.pairs) {
    ps.own["sc1"] = 1.5;
    ps.own["sc2"] = 1.0;
  }
  return spec;
}

// Single-particle DPD with w = (1 - r/r_d)^{1/2} along e and its own exponent across e for one pair (the
// pow form of w_perp for every pair).
SimulationSpec spdpd_own_exponent() {
  SimulationSpec spec = three_species(style_named("spdpd"), 0.5);
  spec.pairs[3].own["s_perp"] = 1.3;
  return spec;
}

// Smoothed DPD with the given kernel and equation-of-state exponent.
SimulationSpec sdpd_species(DensityKernelChoice kernel, double eos_exponent) {
  SimulationSpec spec = three_species(style_named("sdpd"), 2.0);
  spec.pair_section.kernel = kernel;
  for (PairSpec& ps : spec.pairs) {
    ps.own["eos_exponent"] = eos_exponent;
    // Tait's law: a reference density near the random configuration's mass densities (about 4-8 with
    // the self term), so that (rho/rho_0)^7 stays moderate and the forces within the range where their
    // double sum over particles is exact (the test asks it to cancel to zero).
    if (eos_exponent == 7.0) ps.own["rho0"] += 4.0;
  }
  return spec;
}

// The many-body spec with the given density kernel.
SimulationSpec mdpd_species(DensityKernelChoice kernel, double s) {
  SimulationSpec spec = three_species(PairStyle::Mdpd, s);
  spec.pair_section.kernel = kernel;
  return spec;
}

void expect_close(double got, double want, const std::string& what) {
  if (kExact)
    EXPECT_EQ(got, want) << what;
  else
    EXPECT_NEAR(got, want, 2e-3 * (1.0 + std::abs(want))) << what;
}

// Every SIMD target this CPU supports and the pair loop was compiled for, best first.
std::vector<std::int64_t> simd_targets() { return ForceCompute::simd_targets(); }

struct RestoreTargets {
  ~RestoreTargets() { hwy::SetSupportedTargetsForTest(0); }
};

}  // namespace

TEST(PairLoop, EveryLawEqualsTheReferenceLoop) {
  RestoreTargets restore;
  const Box box{{7.3, 6.1, 8.4}};
  struct LawCase {
    std::string name;
    SimulationSpec spec;
  };
  // DPD with each closed-form weight and the general pow form, the soft law, many-body DPD with both
  // density kernels (local densities from the fast density pass, which DensityPassEqualsBruteForceSum
  // checks against the reference) and Liu's splines.
  const std::vector<LawCase> cases = {{"dpd s=2", three_species(PairStyle::Dpd, 2.0)},
                                      {"dpd s=1", three_species(PairStyle::Dpd, 1.0)},
                                      {"dpd s=1/2", three_species(PairStyle::Dpd, 0.5)},
                                      {"dpd s=1/4", three_species(PairStyle::Dpd, 0.25)},
                                      {"dpd s=1.7", three_species(PairStyle::Dpd, 1.7)},
                                      {"soft", three_species(PairStyle::Soft, 2.0)},
                                      {"mdpd warren", mdpd_species(DensityKernelChoice::Warren, 2.0)},
                                      {"mdpd lucy s=1", mdpd_species(DensityKernelChoice::Lucy, 1.0)},
                                      {"spline", three_species(PairStyle::Spline, 2.0)},
                                      {"spline s=1/2", three_species(PairStyle::Spline, 0.5)},
                                      {"edpd", three_species(style_named("edpd"), 2.0)},
                                      {"edpd s=1/2", three_species(style_named("edpd"), 0.5)},
                                      {"edpd s=2 plain", edpd_plain(2.0)},
                                      {"edpd s(T)", edpd_with_s_of_t(false)},
                                      {"edpd s(T) a_t=0.7", edpd_with_s_of_t(true)},
                                      {"tdpd", three_species(style_named("tdpd"), 2.0)},
                                      {"tdpd general", tdpd_general()},
                                      {"sdpd lucy linear", sdpd_species(DensityKernelChoice::Lucy, 1.0)},
                                      {"sdpd wendland tait", sdpd_species(DensityKernelChoice::Wendland, 7.0)},
                                      {"sdpd lucy n=2.5", sdpd_species(DensityKernelChoice::Lucy, 2.5)},
                                      {"spdpd", three_species(style_named("spdpd"), 2.0)},
                                      {"spdpd s=1/2 s_perp", spdpd_own_exponent()}};
  std::uint64_t seed = 11;
  int compared = 0;
  std::string names;
  for (std::int64_t t : simd_targets()) names += std::string(" ") + hwy::TargetName(t);
  for (const LawCase& lc : cases) {
    const PairLawTables laws = make_pair_laws(lc.spec);
    const std::optional<DensitySettings> density = make_density_settings(lc.spec);
    for (NoiseKind noise : {NoiseKind::Uniform, NoiseKind::Gaussian}) {
      ParticleData start = random_particles(box, 1100, 3, seed++);
      // Laws with scalars: eDPD's temperature from 0.6 to 1.8; tDPD's first two concentrations (of four:
      // the loop must skip the channels a run does not hold), from 0 to 3.
      const PairLawInfo& info = pair_law(lc.spec.pair_style);
      const int scalars = info.style == "tdpd" ? std::min(info.scalars, 2) : info.scalars;
      const bool temperature = scalars > 0;
      std::mt19937_64 rng(seed);
      for (int c = 0; c < scalars; ++c) {
        start.enable(info.scalar_fields[static_cast<std::size_t>(c)]);
        start.enable(info.scalar_rates[static_cast<std::size_t>(c)]);
        // (single-particle DPD: angular velocities from -3 to 3)
        std::uniform_real_distribution<double> t(info.style == "edpd" ? 0.6 : (info.style == "spdpd" ? -3.0 : 0.0),
                                                 info.style == "edpd" ? 1.8 : 3.0);
        for (double& v : *start.doubles(info.scalar_fields[static_cast<std::size_t>(c)])) v = t(rng);
      }
      auto rates = [&](ParticleData& q) {
        std::vector<double> out;
        for (int c = 0; c < scalars; ++c) {
          const std::vector<double>& v = *q.doubles(info.scalar_rates[static_cast<std::size_t>(c)]);
          out.insert(out.end(), v.begin(), v.begin() + static_cast<std::ptrdiff_t>(q.n_local));
        }
        return out;
      };
      for (double skin : {0.0, 0.3}) {  // cell pairs, Verlet list
        for (std::int64_t target : simd_targets()) {
          hwy::SetSupportedTargetsForTest(target);
          for (int threads : {1, 2, 3}) {
            omp_set_num_threads(threads);
            ParticleData p = start;
            NeighborList list(NeighborSettings{max_cutoff(laws), skin, true});
            list.build(p, box);
            ForceCompute cpu(laws, NoiseSettings{99, noise});
            PairBackend& fc = cpu;  // as the engine holds it (engine/pair_backend.hpp)
            std::vector<double> rho(p.size());  // the caller sizes it (locals and ghosts)
            if (density) fc.compute_density(p, box, list, *density, rho, nullptr);
            // Forces alone (the usual step: vector fixed-point conversion), then forces with the sums
            // (thermo steps: scalar conversion); both must give the reference's forces.
            PairSums sums;
            fc.compute(p, box, list, 17, 0.04, false, sums, nullptr, density ? rho.data() : nullptr);
            const std::vector<double> fx_plain = p.fx, fy_plain = p.fy, fz_plain = p.fz;
            const std::vector<double> rate_plain = rates(p);
            fc.compute(p, box, list, 17, 0.04, true, sums, nullptr, density ? rho.data() : nullptr);
            EXPECT_TRUE(fx_plain == p.fx && fy_plain == p.fy && fz_plain == p.fz);
            EXPECT_TRUE(rate_plain == rates(p));
            std::vector<std::array<double, 3>> f;
            PairSums ref;
            std::vector<double> rate;
            reference_forces(p, box, laws, NoiseSettings{99, noise}, 17, 0.04, f, ref, density ? rho.data() : nullptr,
                             &rate);
            const std::string what = lc.name + (noise == NoiseKind::Uniform ? " uniform" : " gaussian") +
                                     " skin " + std::to_string(skin) + " " + hwy::TargetName(target) + " threads " +
                                     std::to_string(threads);
            double total[3] = {0, 0, 0};
            for (std::size_t i = 0; i < p.n_local; ++i) {
              expect_close(p.fx[i], f[i][0], what + " fx of id " + std::to_string(p.id[i]));
              expect_close(p.fy[i], f[i][1], what + " fy");
              expect_close(p.fz[i], f[i][2], what + " fz");
              ASSERT_TRUE(std::isfinite(p.fx[i]) && std::isfinite(p.fy[i]) && std::isfinite(p.fz[i])) << what;
              total[0] += p.fx[i];
              total[1] += p.fy[i];
              total[2] += p.fz[i];
              for (int c = 0; c < scalars; ++c) {
                const double got = (*p.doubles(info.scalar_rates[static_cast<std::size_t>(c)]))[i];
                expect_close(got, rate[static_cast<std::size_t>(c) * p.n_local + i],
                             what + " rate of scalar " + std::to_string(c) + " of id " + std::to_string(p.id[i]));
                ASSERT_TRUE(std::isfinite(got)) << what;
              }
            }
            if (temperature) {  // the rates are not all zero: the test compares something
              double largest = 0;
              for (const double r : rate) largest = std::max(largest, std::abs(r));
              EXPECT_GT(largest, 1e-3) << what;
            }
            // Fixed-point sums: the pair forces cancel exactly (Newton's third law, momentum conserved).
            EXPECT_EQ(total[0], 0.0) << what;
            EXPECT_EQ(total[1], 0.0) << what;
            EXPECT_EQ(total[2], 0.0) << what;
            for (std::size_t c = 0; c < 6; ++c) expect_close(sums.virial[c], ref.virial[c], what + " virial");
            expect_close(sums.virial_conservative, ref.virial_conservative, what + " conservative virial");
            expect_close(sums.potential_energy, ref.potential_energy, what + " energy");
            EXPECT_EQ(sums.pairs_in_range, ref.pairs_in_range) << what;
            EXPECT_GT(ref.pairs_in_range, 5000u) << what;  // the configuration is dense enough to test
            ++compared;
          }
        }
      }
    }
  }
  omp_set_num_threads(1);
  EXPECT_GE(compared, static_cast<int>(cases.size()) * 2 * 2 * 3);
  std::printf("SIMD targets tested:%s\n", names.c_str());
}

TEST(PairLoop, ExtremeForcesConvertLikeTheReference) {
  // Force components from 1e-3 to 1e13 (amplitudes a up to 1e13): the fixed-point conversion's fast
  // path (below 2^51 / 2^32 = 524,288 force units), its full path, and the clamp at 9e18 / 2^32, mixed
  // within vectors. A particle with NaN velocity makes NaN forces, which must become the clamp's largest
  // value as in to_fixed(). Every SIMD target against the reference loop, with and without sums. (In the
  // single-precision build pair forces of 1e12 carry float rounding of 1e5 that cancels differently
  // from the double reference's: there the runs without and with sums, whose conversions differ, must
  // agree bit for bit instead.)
  RestoreTargets restore;
  const Box box{{6.2, 5.9, 6.5}};
  SimulationSpec spec = three_species(PairStyle::Dpd, 2.0);
  const double scale[6] = {1.0, 1e5, 1e8, 1e11, 1e13, 3e5};
  for (int k = 0; k < 6; ++k) spec.pairs[static_cast<std::size_t>(k)].a *= scale[k];
  const PairLawTables laws = make_pair_laws(spec);
  ParticleData start = random_particles(box, 700, 3, 123);
  start.vx[17] = std::nan("");
  int compared = 0;
  for (std::int64_t target : simd_targets()) {
    hwy::SetSupportedTargetsForTest(target);
    std::vector<double> plain;  // forces of the run without sums
    for (bool with_sums : {false, true}) {
      ParticleData p = start;
      NeighborList list(NeighborSettings{max_cutoff(laws), 0.0, true});
      list.build(p, box);
      std::vector<std::array<double, 3>> f;
      PairSums ref;
      reference_forces(p, box, laws, NoiseSettings{5, NoiseKind::Uniform}, 3, 0.04, f, ref);
      int huge = 0, clamped = 0;
      for (std::size_t i = 0; i < p.n_local; ++i)
        for (double v : f[i]) {
          huge += std::abs(v) > 524288.0 ? 1 : 0;
          clamped += std::abs(v) > 2e9 ? 1 : 0;  // 9e18 / 2^32 = 2.1e9
        }
      EXPECT_GT(huge, 100);
      EXPECT_GT(clamped, 10);
      ForceCompute fc(laws, NoiseSettings{5, NoiseKind::Uniform});
      PairSums sums;
      fc.compute(p, box, list, 3, 0.04, with_sums, sums, nullptr, nullptr);
      const std::string what = std::string(hwy::TargetName(target)) + (with_sums ? " with sums" : "");
      std::vector<double> got;
      for (std::size_t i = 0; i < p.n_local; ++i) got.insert(got.end(), {p.fx[i], p.fy[i], p.fz[i]});
      if (!with_sums) plain = got;
      EXPECT_TRUE(got == plain) << what;
      if (kExact) {
        for (std::size_t i = 0; i < p.n_local; ++i) {
          EXPECT_EQ(p.fx[i], f[i][0]) << what << " fx of id " << p.id[i];
          EXPECT_EQ(p.fy[i], f[i][1]) << what << " fy of id " << p.id[i];
          EXPECT_EQ(p.fz[i], f[i][2]) << what << " fz of id " << p.id[i];
        }
      }
      ++compared;
    }
  }
  EXPECT_GE(compared, 2);
}

// The analyses' pair loop (cells) must visit exactly the pairs of the brute-force loop, in the same
// order and with the same displacements, on periodic and bounded boxes, with cells exactly as wide as
// the cutoff (box lengths that are multiples of it) and on thin axes of one or two cells (each distinct
// neighbour cell once), periodic and bounded.
TEST(PairLoop, BinnedReferencePairsAreTheBruteForcePairs) {
  struct Case {
    Box box;
    double cutoff;
    std::size_t min_pairs;
  };
  Case periodic{Box{{9.0, 7.0, 6.0}, {true, true, true}}, 1.0, 1000};
  Case bounded{Box{{8.0, 6.5, 7.0}, {true, false, true}}, 1.2, 1000};
  Case thin{Box{{6.0, 2.5, 6.0}, {true, true, true}}, 1.0, 1000};  // two cells along y
  Case thinner{Box{{6.0, 1.5, 6.0}, {true, true, true}}, 1.0, 1000};  // one cell along y
  Case thin_bounded{Box{{6.0, 2.5, 6.0}, {true, false, true}}, 1.0, 1000};  // two cells, bounded
  Case sparse{Box{{40.0, 40.0, 40.0}, {true, true, true}}, 1.5, 30};  // 26^3 cells coarsened to 22^3
  for (const Case& c : {periodic, bounded, thin, thinner, thin_bounded, sparse}) {
    ParticleData p = test::random_particles(c.box, 900, 17, 2, 7, 5);
    // Particles on cell faces and on the box faces, where rounding decides the cell.
    for (std::size_t k = 0; k < 60; ++k) {
      p.x[k] = c.cutoff * static_cast<double>(k % 6);
      p.y[k] = k % 2 == 0 ? 0.0 : std::nextafter(c.box.len.y, 0.0);
    }
    using Visit = std::tuple<std::size_t, std::size_t, double, double, double, double>;
    std::vector<Visit> brute, binned;
    reference_pairs(p, c.box, c.cutoff, false,
                    [&](std::size_t i, std::size_t j, double dx, double dy, double dz, double r) { brute.emplace_back(i, j, dx, dy, dz, r); });
    reference_pairs(p, c.box, c.cutoff, true,
                    [&](std::size_t i, std::size_t j, double dx, double dy, double dz, double r) { binned.emplace_back(i, j, dx, dy, dz, r); });
    EXPECT_GT(brute.size(), c.min_pairs);
    EXPECT_EQ(binned, brute);
  }
}

TEST(PairLoop, DensityPassEqualsBruteForceSum) {
  // Warren's w_rho = 15/(2 pi r_d^3)(1 - r/r_d)^2 and Lucy's kernel; per species pair r_d. The fast loop
  // must equal the reference bit for bit (double build), and the reference a plain double brute-force
  // sum to rounding.
  RestoreTargets restore;
  const Box box{{6.0, 7.5, 5.2}};
  const ParticleData start = random_particles(box, 950, 2, 5);
  for (DensityKernelKind kind : {DensityKernelKind::Warren, DensityKernelKind::Lucy}) {
    DensitySettings ds;
    ds.kernel = kind;
    ds.table.n_species = 2;
    const double rd[4] = {0.75, 0.9, 0.9, 0.6};
    for (double r : rd) ds.table.params.push_back({r, r * r});
    ds.table.max_cutoff = 0.9;
    for (std::int64_t target : simd_targets()) {
      hwy::SetSupportedTargetsForTest(target);
      for (int threads : {1, 2}) {
        omp_set_num_threads(threads);
        for (double skin : {0.0, 0.3}) {
          ParticleData p = start;
          NeighborList list(NeighborSettings{1.0, skin, true});  // a list longer than r_d is fine
          list.build(p, box);
          ForceCompute fc(make_pair_laws(three_species(PairStyle::Dpd, 2.0)), NoiseSettings{});
          std::vector<double> rho(p.size());
          fc.compute_density(p, box, list, ds, rho, nullptr);
          // The caller sizes the array (locals and ghosts); a short one is refused, not overrun.
          std::vector<double> short_rho(p.size() - 1);
          EXPECT_THROW(fc.compute_density(p, box, list, ds, short_rho, nullptr), std::invalid_argument);
          std::vector<double> ref;
          reference_density(p, box, ds, ref);
          const std::string what = std::string(kind == DensityKernelKind::Warren ? "warren " : "lucy ") +
                                   hwy::TargetName(target) + " threads " + std::to_string(threads);
          double mean = 0;
          for (std::size_t i = 0; i < p.n_local; ++i) {
            expect_close(rho[i], ref[i], what + " id " + std::to_string(p.id[i]));
            // Independent plain sum for a few particles.
            if (i % 97 == 0) {
              double plain = 0;
              for (std::size_t j = 0; j < p.n_local; ++j) {
                if (j == i) continue;
                const double dx = minimum_image(p.x[i] - p.x[j], box.len.x, 0.5 * box.len.x);
                const double dy = minimum_image(p.y[i] - p.y[j], box.len.y, 0.5 * box.len.y);
                const double dz = minimum_image(p.z[i] - p.z[j], box.len.z, 0.5 * box.len.z);
                const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
                const double d = ds.table(p.species[i], p.species[j]).rd;
                if (r >= d) continue;
                const double q = r / d, om = 1 - q;
                plain += kind == DensityKernelKind::Warren
                             ? 15.0 / (2 * M_PI * d * d * d) * om * om
                             : 105.0 / (16 * M_PI * d * d * d) * (1 + 3 * q) * om * om * om;
              }
              EXPECT_NEAR(ref[i], plain, 1e-8 * (1 + plain)) << what;
            }
            mean += rho[i];
          }
          // Normalised kernels: the mean local density of an ideal gas is about the number density
          // (species-dependent ranges make it differ a little; a broken kernel is far off).
          mean /= static_cast<double>(p.n_local);
          EXPECT_NEAR(mean, static_cast<double>(p.n_local) / box.volume(), 0.5) << what;
        }
      }
    }
  }
  omp_set_num_threads(1);
}

TEST(PairLoop, SoftFluidConservesEnergyWithoutThermostat) {
  // The soft law has no dissipative or random part, and Groot-Warren with lambda = 1/2 is velocity
  // Verlet: the total energy must fluctuate by O(dt^2) and not drift. A loop that dropped or doubled
  // pairs, or a force inconsistent with the energy, would break the dt^2 scaling.
  SimulationSpec spec = test::fluid_spec(6, 6, 6, 3.0, 10.0, 0.0);
  spec.pair_style = PairStyle::Soft;
  {
    Simulation sim(spec, RunOptions{});
    EXPECT_GT(sim.thermo().potential_energy, 0.0);
  }
  auto worst_deviation = [&](double dt) { return test::worst_energy_deviation(spec, dt); };
  const double coarse = worst_deviation(0.01), fine = worst_deviation(0.005);
  EXPECT_LT(coarse, 5e-3);
  // Halving dt divides the deviation by about four (second-order integrator, exact pair forces).
  EXPECT_GT(coarse / fine, 3.0) << coarse << " " << fine;
  EXPECT_LT(coarse / fine, 5.5) << coarse << " " << fine;
}
