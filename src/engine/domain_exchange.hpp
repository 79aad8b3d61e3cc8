// Where the neighbour search meets the domain decomposition: the box boundaries applied to positions,
// migration to the owning ranks, the cell sort, ghost copies and the neighbour list, in that order.
// neighbor/ knows nothing of ranks and parallel/ nothing of neighbour lists (docs/architecture.md,
// "Module dependencies").
#pragma once
#include <cstdint>
#include <optional>

#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/halo.hpp"

namespace mesodpd {

// A particle found outside [0, L) along a bounded axis: nothing there keeps it in the box yet.
struct EscapedParticle {
  std::uint32_t id = 0;   // the smallest such id over all ranks
  int axis = 0;           // the first bounded axis (x, y, z order) it left the box along
  double x = 0, y = 0, z = 0;
};

// Wraps the local particles' positions into [0, L) along periodic axes, counting crossings in the image
// counters. Along bounded axes nothing is moved; a particle outside [0, L) there is reported (the same
// answer on every rank, collective under MPI, so every rank can stop together). A box periodic on
// every axis costs no communication.
std::optional<EscapedParticle> apply_box_boundaries(ParticleData& p, const Box& box, const Comm& comm);

// Full rebuild: sends every local particle to the rank that owns its cell (when `halo` is active),
// sorts the locals by cell, appends the ghosts and builds the list. Collective under MPI.
void rebuild_neighbors(NeighborList& list, ParticleData& p, const Box& box, Halo& halo,
                       ParticleData::Forces forces = ParticleData::Forces::Discard);

// The neighbour stage of a step: a full rebuild when some particle on any rank has moved half the
// skin (every step in cell-pair mode), otherwise only the ghosts' positions and velocities are
// refreshed. Returns true when it rebuilt. Collective under MPI.
bool update_neighbors(NeighborList& list, ParticleData& p, const Box& box, Halo& halo);

}  // namespace mesodpd
