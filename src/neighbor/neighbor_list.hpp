// Half neighbour list (each unordered pair once) with a Verlet skin, built in O(N) from a cell grid.
#pragma once
#include <cstdint>
#include <vector>

#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "neighbor/cell_grid.hpp"
#include "parallel/halo.hpp"

namespace mesodpd {

struct NeighborSettings {
  double cutoff = 1.0;  // largest interaction range
  double skin = 0.3;    // extra shell; the list stays valid until some particle moves skin/2
  bool sort = true;     // reorder particles by cell at each rebuild (memory locality)
};

class NeighborList {
 public:
  explicit NeighborList(NeighborSettings s) : settings_(s) {}

  // True when some particle (on any rank of `halo`) moved more than skin/2 since the last build (or
  // none was built).
  bool needs_rebuild(const ParticleData& p, const Box& box, const Halo* halo = nullptr) const;

  // Optionally sorts `p` by cell, then lists every unordered pair once whose minimum-image distance
  // is below cutoff + skin (or, in cell-pair mode, only bins and sorts). With an active `halo`, first
  // migrates particles to their owners and afterwards appends the ghosts, sorted by ghost cell; rows
  // are listed for local particles only and their partners may be ghosts.
  void build(ParticleData& p, const Box& box, Halo* halo = nullptr);

  // Cell-pair mode: with no skin the list would be rebuilt every step anyway, so build() only bins and
  // sorts the particles, and the force loop visits cell pairs directly (ForceCompute). Needs sorting and
  // at least three cells per direction; otherwise a list is built.
  bool cells_only() const { return cells_only_; }
  const CellGrid& grid() const { return grid_; }
  // Particles of cell c occupy storage [cell_start()[c], cell_start()[c+1]) after a sorted build; owned
  // cells come first (grid().num_owned_cells()), then ghost cells.
  const std::vector<std::uint32_t>& cell_start() const { return cell_start_; }

  // Row i holds the partners j of particle i: neighbors()[offsets()[i] .. offsets()[i+1]).
  const std::vector<std::uint32_t>& offsets() const { return offsets_; }
  const std::vector<std::uint32_t>& neighbors() const { return neighbors_; }
  std::uint64_t builds() const { return builds_; }
  const NeighborSettings& settings() const { return settings_; }

 private:
  NeighborSettings settings_;
  CellGrid grid_;
  Box grid_box_;
  std::vector<std::uint32_t> cell_start_, cell_index_, order_, ghost_count_;
  std::vector<std::uint32_t> offsets_, neighbors_;
  std::vector<std::vector<std::uint32_t>> thread_rows_;
  std::vector<std::uint32_t> thread_cell_slots_;  // counting sort: per thread and cell, count then first slot
  std::vector<std::uint64_t> thread_block_sums_;
  std::vector<double> x0_, y0_, z0_;  // positions at the last build
  std::uint64_t builds_ = 0;
  bool cells_only_ = false;
};

}  // namespace mesodpd
