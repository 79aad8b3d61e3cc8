// Structure-of-arrays particle storage: local particles in [0, n_local), ghost copies after them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mesodpd {

// Owns every per-particle array. Code that reorders particles goes through permute(), so no array can
// be forgotten. Ghosts (copies of particles owned elsewhere, for domain decomposition) occupy
// [n_local, n_local + n_ghost); a single-domain periodic run needs none, because pair displacements
// use the minimum image (core/box.hpp).
struct ParticleData {
  std::size_t n_local = 0;
  std::size_t n_ghost = 0;

  std::vector<std::uint32_t> id;       // global id, unique and stable for the whole run
  std::vector<std::int32_t> species;   // index into the species table
  std::vector<double> x, y, z;         // wrapped positions in [0, L)
  std::vector<double> vx, vy, vz;      // velocities (during the force stage: the predicted velocity)
  std::vector<double> fx, fy, fz;      // total force of the last force evaluation
  std::vector<double> hx, hy, hz;      // integrator scratch: half-step velocity of modified velocity-Verlet
  std::vector<std::int32_t> ix, iy, iz;  // periodic image counters: unwrapped x = x + ix * Lx

  std::size_t size() const { return n_local + n_ghost; }

  // Growing keeps 1/8 headroom rather than the standard library's doubling: appending ghosts (a few
  // per cent of the locals) must not double the memory of every array.
  void resize(std::size_t n) {
    const std::size_t room = n + n / 8;
    auto grow = [&](auto& v, auto zero) {
      if (n > v.capacity()) v.reserve(room);
      v.resize(n, zero);
    };
    for (auto* v : {&x, &y, &z, &vx, &vy, &vz, &fx, &fy, &fz, &hx, &hy, &hz}) grow(*v, 0.0);
    for (auto* v : {&species, &ix, &iy, &iz}) grow(*v, std::int32_t{0});
    grow(id, std::uint32_t{0});
  }

  // Reorder local particles so that new index k holds old index order[k]; ghosts are dropped. The
  // arrays keep room for `capacity` particles (ghosts to be appended without a reallocation). With
  // `forces` = Forces::Discard the force arrays are resized but not reordered (their contents are then
  // meaningless): for callers that recompute every force before reading one, which saves 3 of the 17
  // arrays of memory traffic.
  enum class Forces { Keep, Discard };
  void permute(const std::vector<std::uint32_t>& order, std::size_t capacity = 0, Forces forces = Forces::Keep);

 private:
  // Spare buffers that permute() gathers into and swaps with, kept so that sorting every step does not
  // allocate (a fresh allocation of this size costs page faults, which do not parallelise).
  std::vector<double> spare_real_;
  std::vector<std::int32_t> spare_int_;
  std::vector<std::uint32_t> spare_id_;
};

}  // namespace mesodpd
