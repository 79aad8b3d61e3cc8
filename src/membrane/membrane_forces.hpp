// The forces of a triangulated elastic membrane (red blood cell models of Fedosov, Caswell & Karniadakis,
// Biophys. J. 98, 2215 (2010) and Comput. Methods Appl. Mech. Eng. 199, 1937 (2010), cited by seed 000
// Sect. 4.4 and seed 002 "Red Cells"), each the exact negative gradient of its energy:
//
//   in-plane elasticity, per edge of length l (worm-like chain plus a power-law repulsion, WLC-POW):
//     U = kT l_m/(4p) (3x^2 - 2x^3)/(1 - x) + k_p/((m - 1) l^(m - 1)),  x = l/l_m  (k_p ln-form at m = 1);
//     l_m = l0/x0 per edge, and k_p set per edge so the force vanishes at its rest length l0 (the
//     stress-free model: l0 the edge's length in the reference shape), or from the mean l0 for all edges;
//   bending, per edge shared by two triangles with normals at angle theta (positive where convex):
//     Kantor-Nelson:  U = k_b [1 - cos(theta - theta0)];
//     Juelicher:      U = 2 kappa sum_i M_i^2 / A_i,  M_i = 1/4 sum_{edges at i} l theta,  A_i = 1/3 sum of
//                     the areas of the triangles at i (integrates kappa/2 (2H)^2: 8 pi kappa for a sphere);
//   area and volume:  U = k_a (A - A0)^2/(2 A0) + sum_t k_d (A_t - A0_t)^2/(2 A0_t) + k_v (V - V0)^2/(2 V0).
//
// Membrane viscosity (Fedosov, Caswell & Karniadakis 2010, their dissipative and random edge forces),
// per edge i-j with unit vector e = (x_i - x_j)/|x_i - x_j| and v_ij = v_i - v_j, on i (minus on j):
//     F^D = -gamma_T v_ij - gamma_C (v_ij . e) e,
//     F^R dt = sqrt(2 kT) [sqrt(2 gamma_T) dW^S + sqrt(3 gamma_C - gamma_T) tr(dW)/3 1] . e,
// dW a 3x3 matrix of independent Wiener increments per edge and step, dW^S its symmetric traceless part.
// The covariance of F^R is 2 kT (gamma_T 1 + gamma_C e e) / dt, twice kT times the friction matrix of
// F^D: the fluctuation-dissipation theorem (needs 3 gamma_C >= gamma_T). The membrane's shear viscosity
// is eta_m = sqrt(3) (gamma_T + gamma_C / 4) (Fedosov et al. 2010).
//
// Forces are sums of gradients of lengths, dihedral angles, triangle areas and the enclosed volume, all
// translation and rotation invariant, so the total force and torque are zero.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/philox.hpp"
#include "membrane/mesh.hpp"

namespace mesodpd::membrane {

enum class Bending { None, KantorNelson, Juelicher };

struct Parameters {
  double kT = 1.0;           // the energy scale of the worm-like chain
  double persistence = 0.0;  // p; 0: no WLC-POW bonds
  double x0 = 1.0 / 2.2;     // l0 / l_m (Fedosov et al. 2010 use l_m = 2.2 l0)
  double m = 2.0;            // exponent of the power-law repulsion
  bool stress_free = true;   // per-edge rest lengths (and triangle areas) from the reference shape
  Bending bending = Bending::None;
  double kb = 0.0, theta0 = 0.0;  // Kantor-Nelson
  double kappa = 0.0;             // Juelicher
  double ka = 0.0, kd = 0.0, kv = 0.0;
  double area0 = 0.0, volume0 = 0.0;  // targets A0, V0; 0: the reference shape's
  double gamma_t = 0.0, gamma_c = 0.0;  // membrane viscosity (3 gamma_C >= gamma_T)
  NoiseKind noise = NoiseKind::Uniform;  // the distribution of the random force's variates
};

// The noise of the edge between vertices with global ids a and b at `step`: nine independent variates of
// mean 0 and variance 1 (the matrix dW / sqrt(dt), row-major), the same for (a, b) and (b, a), a pure
// function of (seed, step, min id, max id): three Philox draws of the membrane's own streams. Uniform
// (the default, as the engine's pair noise, seed 000 Eq. 5: the same first two moments, a tenth of the
// cost) or Gaussian (Box-Muller).
void edge_noise(std::uint64_t seed, std::uint64_t step, std::uint32_t a, std::uint32_t b, double w[9],
                NoiseKind noise = NoiseKind::Uniform);

struct Energies {
  double bond = 0, bend = 0, area_local = 0, area_global = 0, volume = 0;
  double total() const { return bond + bend + area_local + area_global + volume; }
};

// The state of a membrane at rest: its mesh and everything its forces compare with.
class CellModel {
 public:
  // `reference`: the stress-free shape, in the mesh's vertex order (default: the mesh's own vertices).
  CellModel(Mesh mesh, Parameters params, const std::vector<Vec3>* reference = nullptr, const std::string& source = "mesh");
  const Mesh& mesh() const { return mesh_; }
  const Parameters& params() const { return params_; }
  const std::vector<Hinge>& hinges() const { return hinges_; }
  double area0() const { return area0_; }
  double volume0() const { return volume0_; }
  double mean_length() const { return mean_l0_; }
  std::size_t vertex_count() const { return mesh_.vertices.size(); }

  // Adds the membrane forces on the positions x (unwrapped, in vertex order) to f and returns the
  // energies; or, where an edge reaches its maximum length l_m, returns nothing and names the edge in
  // `broken` (the hinge index) and adds no force.
  std::optional<Energies> forces(const std::vector<Vec3>& x, std::vector<Vec3>& f, std::size_t* broken = nullptr) const;
  Energies energies(const std::vector<Vec3>& x) const;

  // Adds the membrane viscosity's dissipative and random forces (the header's formulas) at positions x
  // and velocities v (vertex order) to f: the noise of edge (b, c) is edge_noise(seed, step, first_id + b,
  // first_id + c), so it does not depend on how the vertices are spread over threads or ranks. Nothing
  // where gamma_T = gamma_C = 0.
  void viscous_forces(const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt, std::uint64_t seed,
                      std::uint64_t step, std::uint32_t first_id, std::vector<Vec3>& f) const;
  bool viscous() const { return params_.gamma_t > 0 || params_.gamma_c > 0; }

  // The maximum length of edge k (hinge k's edge).
  double max_length(std::size_t k) const { return l0_[k] / params_.x0; }

 private:
  Mesh mesh_;
  Parameters params_;
  std::vector<Hinge> hinges_;
  std::vector<double> l0_, kp_, area0_t_;  // per hinge (edge), per triangle
  double area0_ = 0, volume0_ = 0, mean_l0_ = 0;
};

// The virial sum over vertices of (x_i - x_0) (x) f_i of forces f that add up to zero (a cell's internal
// forces), in the order of PairSums::virial: xx, yy, zz, then ab = sum (x_b - x_0b) f_a for xy, xz, yz
// (the flux of a-momentum through b-planes, as the pair loop's). The reference vertex x_0 keeps the
// numbers small and does not change the result. For conservative forces W_ab = -dU/d eps_ab under the
// homogeneous deformation x_a -> x_a + eps_ab x_b.
std::array<double, 6> virial(const std::vector<Vec3>& x, const std::vector<Vec3>& f);

// The force magnitude dU/dl of a WLC-POW edge (positive: pulls the ends together) and its energy.
double wlc_pow_dudl(double l, double lm, double kT, double p, double kp, double m);
double wlc_pow_energy(double l, double lm, double kT, double p, double kp, double m);
// k_p that makes the WLC-POW force vanish at l0.
double wlc_pow_kp(double l0, double x0, double kT, double p, double m);

// The linear moduli of a stress-free triangular WLC-POW network of rest length l0 (Fedosov et al.
// 2010): shear mu0 = sqrt(3)/4 U''(l0) (where U'(l0) = 0; the same as their expression
// sqrt(3) kT/(4 p l_m x0) [x0/(2(1-x0)^3) - 1/(4(1-x0)^2) + 1/4] + sqrt(3) k_p (m+1)/(4 l0^(m+1))),
// area compression K = 2 mu0 + k_a + k_d, Young's modulus Y = 4 K mu0 / (K + mu0).
double shear_modulus(double l0, double x0, double kT, double p, double m);
// The persistence length p that gives the shear modulus mu0 (the inverse of the above).
double persistence_for(double mu0, double l0, double x0, double kT, double m);
// Kantor-Nelson's k_b for a bending rigidity kappa: k_b = 2 kappa / sqrt(3) (the continuum limit on a
// regular triangulation of a sphere).
double kantor_nelson_kb(double kappa);
// The membrane shear viscosity of the edge friction: eta_m = sqrt(3) (gamma_T + gamma_C / 4).
double membrane_viscosity(double gamma_t, double gamma_c);

// Shape measures of a cell: centroid, the extents along an axis and across it, area, volume and the
// asphericity of the gyration tensor ((l1-l2)^2 + (l2-l3)^2 + (l1-l3)^2) / (2 (l1+l2+l3)^2).
struct Shape {
  Vec3 centroid;
  double axial = 0;       // max - min of the vertices' coordinate along `axis`
  double transverse = 0;  // largest distance between two vertices projected on the plane normal to `axis`
  double area = 0, volume = 0, asphericity = 0;
};
Shape measure(const Mesh& mesh, const std::vector<Vec3>& x, int axis);

}  // namespace mesodpd::membrane

namespace mesodpd::membrane {

// Optical-tweezers stretching at equilibrium (the experiment of Mills et al., Mech. Chem. Biosystems 1,
// 169 (2004), as Fedosov et al. 2010 simulate it): a total force +F along `axis` spread evenly over the
// fraction `fraction` of the vertices farthest along it in the reference shape, -F over the same
// fraction at the other end. The shape minimises E - F (mean position of the first set - that of the
// second), found by FIRE (Bitzek et al., Phys. Rev. Lett. 97, 170201 (2006)) from `start` until no
// vertex feels more than `tolerance` of net force. Throws if it does not converge in `max_steps`.
// The tweezers' force on each vertex: +force / k on the k = max(1, round(fraction N_v)) vertices farthest
// along `axis` in the mesh's own shape, -force / k on the k nearest (ties by index), zero elsewhere.
std::vector<Vec3> tweezers(const Mesh& mesh, double force, double fraction, int axis);

struct Stretched {
  std::vector<Vec3> x;
  Shape shape;
  std::size_t steps = 0;
  double residual = 0;  // the largest net force on a vertex at the end
};
Stretched stretch(const CellModel& cell, const std::vector<Vec3>& start, double force, double fraction, int axis,
                  double tolerance, std::size_t max_steps = 2000000);

}  // namespace mesodpd::membrane
