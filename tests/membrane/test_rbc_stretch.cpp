// Optical-tweezers stretching of a red cell against Mills et al. (Mech. Chem. Biosystems 1, 169 (2004)),
// the membrane alone at equilibrium (membrane::stretch), with the physical parameters of the issue
// mapped to the model by the analytic network moduli. Units: um, k_BT at 310 K (4.280e-21 J), so
// 1 pN = 233.6 k_BT/um and 1 uN/m = 233.6 k_BT/um^2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "membrane/membrane_forces.hpp"
#include "membrane/mesh.hpp"

namespace mesodpd::membrane {
namespace {

constexpr double kT_joule = 1.380649e-23 * 310.0;
constexpr double pN = 1e-12 * 1e-6 / kT_joule;          // k_BT/um per pN
constexpr double uN_per_m = 1e-6 * 1e-12 / kT_joule;    // k_BT/um^2 per uN/m

CellModel red_cell_model(std::size_t vertices) {
  const Mesh mesh = red_cell(frequency_for(vertices), 7.82);
  Parameters p;
  p.kT = 1.0;
  p.x0 = 1 / 2.2;
  p.m = 2;
  p.stress_free = true;
  const double mu0 = 6.3 * uN_per_m;
  CellModel probe(mesh, p);
  p.persistence = persistence_for(mu0, probe.mean_length(), p.x0, p.kT, p.m);
  p.bending = Bending::Juelicher;
  p.kappa = 2.4e-19 / kT_joule;
  p.ka = 49 * mu0;
  p.kd = mu0;
  p.kv = 50 * mu0;  // per um
  return CellModel(mesh, p);
}

// Mills et al. (their Fig. 3, as the issue quotes it): at 109 pN D_A = 13.6 um and D_T = 4.5 um; at
// 193 pN D_A = 15.3 um (the spread of the cells: 12.95-17.65 um) and D_T = 4.3 um. The test holds the
// model to that spread, +-2.35 um, for D_A at both forces, and to +-0.6 um for D_T; docs/validation.md
// has the whole curve for 500, 1000 and 3000 vertices (the same within 1 %). NV=1000 in the environment
// runs another mesh.
TEST(RedCellStretch, DiametersAgainstMillsOpticalTweezers) {
  const CellModel cell = red_cell_model(std::getenv("NV") ? std::stoul(std::getenv("NV")) : 500);
  std::vector<Vec3> x = cell.mesh().vertices;
  std::printf("  %zu vertices, mean edge %.3f um, p = %.4g um, mu0 = %.4g k_BT/um^2\n", cell.vertex_count(),
              cell.mean_length(), cell.params().persistence,
              shear_modulus(cell.mean_length(), cell.params().x0, 1.0, cell.params().persistence, cell.params().m));
  std::printf("  F (pN)   D_A (um)  D_T (um)  area/A0  volume/V0  steps\n");
  double previous = 0;
  for (double f : {0.0, 16.0, 38.0, 67.0, 88.0, 109.0, 133.0, 151.0, 193.0}) {
    const Stretched s = stretch(cell, x, f * pN, 0.02, 0, 1e-3);
    x = s.x;
    std::printf("  %6.0f  %8.3f  %8.3f  %7.4f  %9.4f  %zu\n", f, s.shape.axial, s.shape.transverse,
                s.shape.area / cell.area0(), s.shape.volume / cell.volume0(), s.steps);
    EXPECT_GT(s.shape.axial, previous);
    previous = s.shape.axial;
    EXPECT_NEAR(s.shape.area / cell.area0(), 1.0, 5e-3);
    EXPECT_NEAR(s.shape.volume / cell.volume0(), 1.0, 5e-3);
    if (f == 0) {
      EXPECT_NEAR(s.shape.axial, 7.82, 0.1);
      EXPECT_NEAR(s.shape.transverse, 7.82, 0.1);
    }
    if (f == 109) {
      EXPECT_NEAR(s.shape.axial, 13.6, 2.35);
      EXPECT_NEAR(s.shape.transverse, 4.5, 0.6);
    }
    if (f == 193) {
      EXPECT_NEAR(s.shape.axial, 15.3, 2.35);
      EXPECT_NEAR(s.shape.transverse, 4.3, 0.6);
    }
  }
}

}  // namespace
}  // namespace mesodpd::membrane
