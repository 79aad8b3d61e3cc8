// Per-particle update loops of the integrators.
#include "integrate/integrator.hpp"

namespace mesodpd {

void GrootWarrenIntegrator::pre_force(ParticleData& p, const std::vector<double>& inv_mass, double dt) const {
  const std::size_t n = p.n_local;
  const double half_dt = 0.5 * dt, half_dt2 = 0.5 * dt * dt, lambda_dt = lambda * dt;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double im = inv_mass[static_cast<std::size_t>(p.species[i])];
    const double ax = p.fx[i] * im, ay = p.fy[i] * im, az = p.fz[i] * im;
    p.x[i] += dt * p.vx[i] + half_dt2 * ax;
    p.y[i] += dt * p.vy[i] + half_dt2 * ay;
    p.z[i] += dt * p.vz[i] + half_dt2 * az;
    p.hx[i] = p.vx[i] + half_dt * ax;
    p.hy[i] = p.vy[i] + half_dt * ay;
    p.hz[i] = p.vz[i] + half_dt * az;
    p.vx[i] += lambda_dt * ax;
    p.vy[i] += lambda_dt * ay;
    p.vz[i] += lambda_dt * az;
  }
}

void GrootWarrenIntegrator::post_force(ParticleData& p, const std::vector<double>& inv_mass, double dt) const {
  const std::size_t n = p.n_local;
  const double half_dt = 0.5 * dt;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double im = inv_mass[static_cast<std::size_t>(p.species[i])] * half_dt;
    p.vx[i] = p.hx[i] + im * p.fx[i];
    p.vy[i] = p.hy[i] + im * p.fy[i];
    p.vz[i] = p.hz[i] + im * p.fz[i];
  }
}

void EulerIntegrator::pre_force(ParticleData& p, const std::vector<double>& inv_mass, double dt) const {
  const std::size_t n = p.n_local;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double im = inv_mass[static_cast<std::size_t>(p.species[i])] * dt;
    p.x[i] += dt * p.vx[i];
    p.y[i] += dt * p.vy[i];
    p.z[i] += dt * p.vz[i];
    p.vx[i] += im * p.fx[i];
    p.vy[i] += im * p.fy[i];
    p.vz[i] += im * p.fz[i];
  }
}

}  // namespace mesodpd
