// Ghost particles and migration for a decomposed box. Exchanges go axis by axis (x, then y, then z) with
// the two neighbours along each split axis, and later axes forward the ghosts of earlier ones, so edge
// and corner ghosts need no diagonal messages. Ghosts keep their owner's wrapped coordinates: pair
// geometry is the minimum image (core/box.hpp), so a pair has the same bits on every rank count.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/particle_data.hpp"
#include "neighbor/cell_grid.hpp"
#include "parallel/comm.hpp"
#include "parallel/decomposition.hpp"

namespace mesodpd {

class Halo {
 public:
  Halo() : comm_(Comm::serial()) {}
  Halo(Comm comm, Decomposition dec) : comm_(comm), dec_(dec) {}

  const Comm& comm() const { return comm_; }
  const Decomposition& decomposition() const { return dec_; }
  // True when some axis is split: ghosts and migration are needed.
  bool active() const { return dec_.any_decomposed(); }
  // The cell block and ghost layers this rank's grid covers.
  CellDomain cell_domain() const;

  // True when a wrapped position lies in this rank's cells (`grid`: the global cell grid).
  bool owns(double x, double y, double z, const CellGrid& grid) const;
  // Drops the local particles another rank owns (after building or reading the whole system).
  void keep_owned(ParticleData& p, const CellGrid& grid) const;
  // Sends every local particle that left this rank's cells to its owner; ghosts are dropped.
  void migrate(ParticleData& p, const CellGrid& grid);
  // Appends ghost copies (id, species, position, velocity) sorted by ghost cell; ghost_counts() then
  // holds the number of ghosts of each ghost cell (index cell - num_owned_cells()). The locals must be
  // sorted by cell, owned cell c holding [cell_start[c], cell_start[c+1]).
  void build_ghosts(ParticleData& p, const CellGrid& grid, std::span<const std::uint32_t> cell_start);
  const std::vector<std::uint32_t>& ghost_counts() const { return ghost_count_; }
  // Refreshes the fields flagged kRefresh (positions and velocities) of the ghosts of the last
  // build_ghosts (Verlet lists).
  void update_ghosts(ParticleData& p);
  // Copies the owners' values of a per-particle quantity (`field[i]` for storage index i, locals and
  // ghosts; at least p.size() entries) to their ghost copies, along the send lists of the last
  // build_ghosts: for a quantity computed on the locals between neighbour builds (a local density)
  // that a later pair pass reads on ghosts too. A no-op when the halo is inactive. Collective.
  void forward_field(ParticleData& p, std::span<double> field);
  // Adds the fixed-point forces accumulated on ghosts (f3: x, y, z per particle, local and ghost) to
  // their owners' entries. Integer sums: the result does not depend on the order of arrival.
  void reverse_forces(std::int64_t* f3, const ParticleData& p) { reverse_sums(f3, 3, p); }
  // The same for any number of integer components per particle (v: `components` entries per particle).
  void reverse_sums(std::int64_t* v, int components, const ParticleData& p);

  // Particles on all ranks after the last migration (0 before the first): particles change ranks
  // only there, so comparing it with the expected total finds a lost or duplicated one.
  std::uint64_t total_after_migration() const { return total_after_migration_; }

  // Seconds spent in migration, ghost construction and refresh and reverse forces since construction
  // (packing, sorting and messages), and the part of it spent in message calls (transfer plus waiting
  // for the neighbour to get there).
  double seconds() const { return seconds_; }
  double message_seconds() const { return message_seconds_; }

 private:
  // Sends `out` to the neighbour on side `dir` of axis d and receives from the other side.
  std::vector<std::byte> swap(int d, int dir, int tag_base, std::span<const std::byte> out);
  // Sends records (of record_bytes, written by pack(storage index, out)) from owners to their ghost
  // copies along the send lists of the last build_ghosts; unpack(in, storage index) stores them.
  template <class Pack, class Unpack>
  void forward(std::size_t record_bytes, int tag_base, Pack&& pack, Unpack&& unpack);
  std::size_t storage_of(std::size_t arrival) const {
    return arrival < n_local_ ? arrival : slot_[arrival - n_local_];
  }

  Comm comm_;
  Decomposition dec_;
  std::size_t n_local_ = 0;                 // locals at the last build_ghosts
  std::array<std::array<std::vector<std::uint32_t>, 2>, 3> send_;  // arrival indices sent, per axis and side
  std::array<std::array<std::size_t, 2>, 3> recv_begin_{}, recv_count_{};  // arrival ranges received
  std::vector<std::uint32_t> slot_;         // ghost arrival order -> storage index
  std::vector<std::uint32_t> ghost_count_;  // ghosts per ghost cell at the last build_ghosts
  double seconds_ = 0;
  double message_seconds_ = 0;
  std::uint64_t total_after_migration_ = 0;
};

// Every rank's local particles, in increasing global id, on the root (empty elsewhere). Collective.
// Checks that exactly `expected` particles with distinct ids exist (none lost or duplicated).
ParticleData gather_by_id(const ParticleData& p, const Comm& comm, std::uint64_t expected);
// The same into `all`, reusing its memory (for output that samples every step).
void gather_by_id(const ParticleData& p, const Comm& comm, std::uint64_t expected, ParticleData& all);

}  // namespace mesodpd
