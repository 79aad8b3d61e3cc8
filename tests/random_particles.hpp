// Random particle configurations for the pair-loop, neighbour-list and boundary tests.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <random>

#include "core/box.hpp"
#include "core/particle_data.hpp"

namespace mesodpd::test {

// n particles placed uniformly in the box with Gaussian velocities and ids first_id, first_id + id_step,
// ...; with `species` > 1, each gets a uniformly drawn species index.
inline ParticleData random_particles(const Box& box, std::size_t n, std::uint64_t seed, int species = 1,
                                     std::uint32_t first_id = 1, std::uint32_t id_step = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  ParticleData p;
  p.resize(n);
  p.n_local = n;
  for (std::size_t i = 0; i < n; ++i) {
    p.id[i] = static_cast<std::uint32_t>(first_id + id_step * i);
    if (species > 1) p.species[i] = static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(species));
    p.x[i] = u(rng) * box.len.x;
    p.y[i] = u(rng) * box.len.y;
    p.z[i] = u(rng) * box.len.z;
    p.vx[i] = g(rng);
    p.vy[i] = g(rng);
    p.vz[i] = g(rng);
  }
  return p;
}

// Positions and velocities of the local particles by id: equal maps mean bit-identical states whatever
// the storage order.
inline std::map<std::uint32_t, std::array<double, 6>> state_by_id(const ParticleData& p) {
  std::map<std::uint32_t, std::array<double, 6>> out;
  for (std::size_t i = 0; i < p.n_local; ++i) out[p.id[i]] = {p.x[i], p.y[i], p.z[i], p.vx[i], p.vy[i], p.vz[i]};
  return out;
}

}  // namespace mesodpd::test
