// The recipe "add a pair force law" of docs/architecture.md, proved with a law that lives outside src/
// (power_law.hpp) and joins the list through one line (extra_law.hpp): this program links a second build
// of the engine, the schema and the api in which PairLawTables holds it. Nothing else names the law:
// the reader, the checks, the errors, the key documentation, the fast pair loop on every SIMD target
// and the reference loop take it from the list.
#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "engine/force_compute.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"
#include "neighbor/neighbor_list.hpp"
#include "energy_drift.hpp"
#include "random_particles.hpp"
#include "test_support.hpp"

namespace mesodpd {
namespace {

using test_models::PowerLaw;

constexpr std::size_t kPowerIndex = kPairLawCount - 1;
static_assert(std::is_same_v<std::variant_alternative_t<kPowerIndex, PairLawTables>::LawType, PowerLaw>);

std::string fluid(const std::string& pair) {
  return "[system]\nbox = [6.0, 6.0, 6.0]\nkT = 1.0\nseed = 5\n[[species]]\nname = \"A\"\ndensity = 3.0\n"
         "[[species]]\nname = \"B\"\ndensity = 1.0\n[pair]\n" +
         pair + "[integrator]\ndt = 0.01\n[run]\nsteps = 10\n";
}

std::string error_of(const std::string& text) {
  try {
    parse_config(text, "law.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

void expect_error(const std::string& text, std::initializer_list<std::string_view> needles) {
  const std::string message = error_of(text);
  for (const std::string_view needle : needles)
    EXPECT_NE(message.find(needle), std::string::npos) << "message: " << message << "\nlacks: " << needle;
}

}  // namespace

TEST(PairLawRecipe, TheStyleAndItsOwnKeyAreReadCheckedAndDocumented) {
  const SimulationSpec spec =
      parse_config(fluid("style = \"test_power\"\na = 30.0\nn = 2.5\n[[pair.override]]\nspecies = [\"A\", \"B\"]\nn = 4\n"),
                   "law.toml");
  EXPECT_EQ(static_cast<std::size_t>(spec.pair_style), kPowerIndex);
  EXPECT_EQ(spec.pair(0, 0).value("n"), 2.5);
  EXPECT_EQ(spec.pair(0, 1).value("n"), 4.0);  // per pair, from the override
  EXPECT_EQ(parse_config(fluid("style = \"test_power\"\n"), "law.toml").pair(1, 1).value("n"), 1.0);  // its default

  // Its range, with the file position; its cross-check on a resolved pair; the shared keys it does not
  // read; its key under another style; and the style list in the error for an unknown style.
  expect_error(fluid("style = \"test_power\"\nn = 7\n"), {"law.toml:", "pair.n = 7", "must be in [1, 6]"});
  expect_error(fluid("style = \"test_power\"\nn = 4\nrc = 0.4\n"), {"pair.n = 4", "above 3 needs rc >= 0.5, not 0.4"});
  expect_error(fluid("style = \"test_power\"\ngamma = 4.5\n"), {"pair.gamma", "not used with pair.style = \"test_power\""});
  expect_error(fluid("n = 2\n"), {"pair.n = 2", "not used with pair.style = \"dpd\""});
  expect_error(fluid("style = \"test_powr\"\n"), {"pair.style", "\"test_power\""});

  // Its rows of docs/config.md: the style's sentence and the own key, marked with its style.
  const std::vector<keys::KeyDoc> rows = pair_key_docs();
  const auto n = std::find_if(rows.begin(), rows.end(), [](const keys::KeyDoc& r) { return r.name == "n"; });
  ASSERT_NE(n, rows.end());
  EXPECT_NE(n->meaning.find("`test_power` only: Exponent n"), std::string::npos) << n->meaning;
  EXPECT_EQ(n->default_text, "1.0");
  EXPECT_NE(rows.front().meaning.find("`test_power`: a test-only power-law"), std::string::npos);
}

TEST(PairLawRecipe, TheFastLoopEqualsTheReferenceLoopOnEverySimdTarget) {
  const Box box{{6.3, 5.9, 7.1}};
  SimulationSpec spec = parse_config(
      fluid("style = \"test_power\"\na = 30.0\nn = 2.5\n[[pair.override]]\nspecies = [\"A\", \"B\"]\nn = 4\nrc = 1.2\n"),
      "law.toml");
  const PairLawTables laws = make_pair_laws(spec);
  ASSERT_EQ(laws.index(), kPowerIndex);
  const ParticleData start = test::random_particles(box, 900, 3, 2, 7, 5);
  int compared = 0;
  for (std::int64_t target : ForceCompute::simd_targets()) {
    hwy::SetSupportedTargetsForTest(target);
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      ParticleData p = start;
      NeighborList list(NeighborSettings{max_cutoff(laws), 0.3, true});
      list.build(p, box);
      ForceCompute cpu(laws, NoiseSettings{3, NoiseKind::Uniform});
      PairSums sums;
      cpu.compute(p, box, list, 4, 0.01, true, sums, nullptr, nullptr);
      std::vector<std::array<double, 3>> f;
      PairSums ref;
      reference_forces(p, box, laws, NoiseSettings{3, NoiseKind::Uniform}, 4, 0.01, f, ref, nullptr);
      for (std::size_t i = 0; i < p.n_local; ++i) {
#ifdef MESODPD_SINGLE_PRECISION
        EXPECT_NEAR(p.fx[i], f[i][0], 2e-3 * (1 + std::abs(f[i][0])));
#else
        EXPECT_EQ(p.fx[i], f[i][0]) << hwy::TargetName(target) << " id " << p.id[i];
        EXPECT_EQ(p.fy[i], f[i][1]);
        EXPECT_EQ(p.fz[i], f[i][2]);
#endif
      }
      EXPECT_NEAR(sums.potential_energy, ref.potential_energy, 1e-9 * std::abs(ref.potential_energy));
      EXPECT_EQ(sums.pairs_in_range, ref.pairs_in_range);
      EXPECT_GT(ref.pairs_in_range, 3000u);
      ++compared;
    }
  }
  hwy::SetSupportedTargetsForTest(0);
  omp_set_num_threads(1);
  EXPECT_GE(compared, 2);
}

TEST(PairLawRecipe, ExponentOneIsTheConservativeForceOfStandardDpd) {
  // n = 1 is F = a (1 - r/r_c), seed 000 Eq. 3; the DPD law with gamma = 0 (and so sigma = 0) has only
  // that force. Both laws on the same particles must give the same forces and energy to rounding.
  const Box box{{6.0, 6.0, 6.0}};
  const ParticleData start = test::random_particles(box, 600, 11, 2, 7, 5);
  auto forces = [&](const std::string& pair, PairSums& sums) {
    const PairLawTables laws = make_pair_laws(parse_config(fluid(pair), "law.toml"));
    ParticleData p = start;
    NeighborList list(NeighborSettings{max_cutoff(laws), 0.0, true});
    list.build(p, box);
    ForceCompute cpu(laws, NoiseSettings{3, NoiseKind::Uniform});
    cpu.compute(p, box, list, 1, 0.01, true, sums, nullptr, nullptr);
    return p;
  };
  PairSums s_power, s_dpd;
  const ParticleData power = forces("style = \"test_power\"\na = 30.0\nn = 1\n", s_power);
  const ParticleData dpd = forces("a = 30.0\ngamma = 0.0\n", s_dpd);
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < power.n_local; ++i) {
    worst = std::max({worst, std::abs(power.fx[i] - dpd.fx[i]), std::abs(power.fy[i] - dpd.fy[i]),
                      std::abs(power.fz[i] - dpd.fz[i])});
    scale = std::max(scale, std::abs(dpd.fx[i]));
  }
  EXPECT_GT(scale, 10.0);
  EXPECT_LT(worst, 1e-9 * scale);
  EXPECT_NEAR(s_power.potential_energy, s_dpd.potential_energy, 1e-9 * s_dpd.potential_energy);
}

TEST(PairLawRecipe, AFluidOfTheNewLawConservesEnergyAtSecondOrder) {
  // Conservative only, integrated by velocity Verlet (Groot-Warren at lambda = 1/2): the total energy
  // deviates by O(dt^2), so halving dt divides the deviation by about four. A force inconsistent with
  // the energy the law reports, or pairs dropped or doubled, breaks this.
  SimulationSpec spec = parse_config(fluid("style = \"test_power\"\na = 20.0\nn = 2\n"), "law.toml");
  spec.thermo_every = 10;
  spec.progress = false;
  {
    Simulation sim(spec, RunOptions{});
    EXPECT_GT(sim.thermo().potential_energy, 0.0);
  }
  auto worst_deviation = [&](double dt) { return test::worst_energy_deviation(spec, dt); };
  const double coarse = worst_deviation(0.01), fine = worst_deviation(0.005);
  EXPECT_LT(coarse, 5e-3);
  EXPECT_GT(coarse / fine, 3.0) << coarse << " " << fine;
  EXPECT_LT(coarse / fine, 5.5) << coarse << " " << fine;
}

}  // namespace mesodpd
