// Where the neighbour search meets the domain decomposition: migration to the owning ranks, the cell
// sort, ghost copies and the neighbour list, in that order. neighbor/ knows nothing of ranks and
// parallel/ nothing of neighbour lists (docs/architecture.md, "Module dependencies").
#pragma once
#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/halo.hpp"

namespace mesodpd {

// Full rebuild: sends every local particle to the rank that owns its cell (when `halo` is active),
// sorts the locals by cell, appends the ghosts and builds the list. Collective under MPI.
void rebuild_neighbors(NeighborList& list, ParticleData& p, const Box& box, Halo& halo);

// The neighbour stage of a step: a full rebuild when some particle on any rank has moved half the
// skin (every step in cell-pair mode), otherwise only the ghosts' positions and velocities are
// refreshed. Returns true when it rebuilt. Collective under MPI.
bool update_neighbors(NeighborList& list, ParticleData& p, const Box& box, Halo& halo);

}  // namespace mesodpd
