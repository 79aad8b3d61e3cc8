// The order of migration, cell sort, ghost construction and list building, for one rank or many.
#include "engine/domain_exchange.hpp"

namespace mesodpd {

void rebuild_neighbors(NeighborList& list, ParticleData& p, const Box& box, Halo& halo) {
  if (!halo.active()) {
    list.build(p, box);
    return;
  }
  list.set_grid(box, halo.cell_domain());
  halo.migrate(p, list.grid());  // drops the old ghosts; particles change ranks only here
  list.sort_locals(p);
  halo.build_ghosts(p, list.grid(), list.cell_start());
  list.finish(p, box, halo.ghost_counts());
}

bool update_neighbors(NeighborList& list, ParticleData& p, const Box& box, Halo& halo) {
  bool rebuild = list.needs_rebuild(p, box);
  // With a skin the answer differs between ranks; all rebuild together (migration and ghosts are
  // collective), exactly when a single rank holding every particle would.
  if (list.settings().skin > 0.0 && halo.comm().distributed())
    rebuild = halo.comm().max(rebuild ? std::uint64_t{1} : std::uint64_t{0}) != 0;
  if (rebuild)
    rebuild_neighbors(list, p, box, halo);
  else
    halo.update_ghosts(p);
  return rebuild;
}

}  // namespace mesodpd
