// Half neighbour list (each unordered pair once) with a Verlet skin, built in O(N) from a cell grid.
// Knows nothing of ranks: under domain decomposition the caller moves particles between the phases of
// a build (engine/domain_exchange.hpp), and hands the ghost cell counts over as data.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "neighbor/cell_grid.hpp"

namespace mesodpd {

struct NeighborSettings {
  double cutoff = 1.0;  // largest interaction range
  double skin = 0.3;    // extra shell; the list stays valid until some particle moves skin/2
  bool sort = true;     // reorder particles by cell at each rebuild (memory locality)
};

class NeighborList {
 public:
  explicit NeighborList(NeighborSettings s) : settings_(s) {}

  // True when some local particle moved more than skin/2 since the last build (or none was built; with
  // Lees-Edwards images the change of the image offset counts against the skin too). This
  // rank's answer only: under MPI the caller combines the answers of all ranks, which rebuild together.
  bool needs_rebuild(const ParticleData& p, const Box& box) const;

  // Single domain: optionally sorts `p` by cell, then lists every unordered pair once whose
  // minimum-image distance is below cutoff + skin (or, in cell-pair mode, only bins and sorts).
  // Equivalent to set_grid(box), sort_locals(p, forces), finish(p, box).
  void build(ParticleData& p, const Box& box, ParticleData::Forces forces = ParticleData::Forces::Discard);

  // The phases of a build, for a caller that moves particles between ranks in between:
  // 1. set_grid: the cell grid of `box` restricted to this rank's block of cells `domain` (kept while
  //    box and domain stay the same). Migration to the owning ranks goes here, using grid().
  // 2. sort_locals: bins the local particles (all must lie in owned cells) and, when sorting or
  //    decomposed, reorders the storage by cell, dropping any ghosts and leaving room for new ones;
  //    cell_start() is then valid for the owned cells. Ghost construction goes here.
  // 3. finish: ghosts [n_local, n_local + n_ghost) must be sorted by ghost cell, ghost_count[k] of
  //    them in cell num_owned_cells() + k; completes cell_start() and lists the pairs, rows for local
  //    particles only (partners may be ghosts).
  void set_grid(const Box& box, const CellDomain& domain = {});
  // (`forces`: Keep carries the forces along, which a build normally leaves unordered.)
  void sort_locals(ParticleData& p, ParticleData::Forces forces = ParticleData::Forces::Discard);
  void finish(ParticleData& p, const Box& box, std::span<const std::uint32_t> ghost_count = {});

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
  // True while the storage of `p` is still in the cell order of the last build (nothing reordered,
  // resized or appended since; the particles may have moved, by at most skin/2 as of the last
  // needs_rebuild() check): the local particles of owned cell c are then at
  // [cell_start()[c], cell_start()[c + 1]).
  bool cell_order_of(const ParticleData& p) const {
    return sorted_generation_ != 0 && sorted_generation_ == p.generation();
  }
  const NeighborSettings& settings() const { return settings_; }

 private:
  NeighborSettings settings_;
  CellGrid grid_;
  Box grid_box_;
  CellDomain grid_domain_;
  bool has_grid_ = false;
  bool decomposed_ = false;  // the grid covers part of the box, with ghost cells
  std::vector<std::uint32_t> cell_start_, cell_index_, order_, ghost_count_;
  std::vector<std::uint32_t> offsets_, neighbors_;
  std::vector<std::vector<std::uint32_t>> thread_rows_;
  std::vector<std::uint32_t> thread_cell_slots_;  // counting sort: per thread and cell, count then first slot
  std::vector<std::uint64_t> thread_block_sums_;
  std::vector<double> x0_, y0_, z0_;  // positions at the last build
  double offset0_ = 0.0;              // the Lees-Edwards image offset at the last build
  std::uint64_t builds_ = 0;
  std::uint64_t sorted_generation_ = 0;  // ParticleData::generation() after the last sorted build
  bool cells_only_ = false;
};

}  // namespace mesodpd
