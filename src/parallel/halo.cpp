// Migration, ghost construction, ghost refresh and reverse force communication.
#include "parallel/halo.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string_view>

namespace mesodpd {

namespace {

// Records are the fields of the particle field list (core/particle_data.hpp) packed back to back:
// a moving particle carries every field flagged kMigrate, a ghost those flagged kGhost, a ghost
// refresh those flagged kRefresh. Adding a field to the list changes the records, not this file. The
// record sizes depend on the optional fields a run holds (the same on every rank: a model enables its
// fields everywhere), so they are taken from the particles.
std::size_t move_bytes(const ParticleData& p) { return p.record_bytes<field::kMigrate>(); }
std::size_t refresh_bytes(const ParticleData& p) { return p.record_bytes<field::kRefresh>(); }
// A ghost record starts with its cell coordinates in the receiver's grid frame (3 x int16 and a pad),
// then the ghost fields.
constexpr std::size_t kCellBytes = 4 * sizeof(std::int16_t);
std::size_t ghost_bytes(const ParticleData& p) { return kCellBytes + p.record_bytes<field::kGhost>(); }

// Ghost records in order of arrival, `record` bytes each.
class GhostRecords {
 public:
  explicit GhostRecords(std::size_t record) : record_(record) {}
  std::size_t size() const { return bytes_.size() / record_; }
  std::byte* append() {
    bytes_.resize(bytes_.size() + record_);
    return bytes_.data() + bytes_.size() - record_;
  }
  void append(const std::byte* record) { std::memcpy(append(), record, record_); }
  std::byte* at(std::size_t g) { return bytes_.data() + g * record_; }
  const std::byte* at(std::size_t g) const { return bytes_.data() + g * record_; }
  std::vector<std::byte>& bytes() { return bytes_; }

 private:
  std::size_t record_;
  std::vector<std::byte> bytes_;
};

std::int16_t cell_coord(const std::byte* record, std::size_t d) {
  std::int16_t c;
  std::memcpy(&c, record + d * sizeof(std::int16_t), sizeof c);
  return c;
}
void set_cell_coord(std::byte* record, std::size_t d, std::int16_t c) {
  std::memcpy(record + d * sizeof(std::int16_t), &c, sizeof c);
}

template <class T>
std::span<const std::byte> as_bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v.data(), v.size()));
}

template <class T>
std::vector<T> records_from(const std::vector<std::byte>& bytes) {
  if (bytes.size() % sizeof(T) != 0) throw std::runtime_error("halo: truncated message");
  std::vector<T> out(bytes.size() / sizeof(T));
  if (!out.empty()) std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

// Number of records of `stride` bytes in a message, refusing a message that is not whole records.
std::size_t record_count(const std::vector<std::byte>& bytes, std::size_t stride) {
  if (bytes.size() % stride != 0) throw std::runtime_error("halo: truncated message");
  return bytes.size() / stride;
}

int tag(int base, int d, int dir) { return base + 2 * d + dir; }

class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
  ~Stopwatch() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }

 private:
  double& total_;
  std::chrono::steady_clock::time_point t0_;
};

const std::vector<double>& coord_array(const ParticleData& p, int d) { return d == 0 ? p.x : (d == 1 ? p.y : p.z); }

}  // namespace

std::vector<std::byte> Halo::swap(int d, int dir, int tag_base, std::span<const std::byte> out) {
  Stopwatch sw(message_seconds_);
  // Past the end of a bounded axis there is no neighbour: nothing goes there and nothing comes back.
  const int dest = dec_.neighbor(d, dir), src = dec_.neighbor(d, 1 - dir);
  if (dest == Decomposition::kNoRank && !out.empty()) throw std::logic_error("halo: a message past a bounded end");
  return comm_.exchange(dest, src, tag(tag_base, d, dir), out);
}

CellDomain Halo::cell_domain() const {
  CellDomain c;
  for (std::size_t d = 0; d < 3; ++d) {
    c.lo[d] = dec_.cell_lo[d];
    c.count[d] = dec_.grid[d] > 1 ? dec_.cell_count[d] : 0;
    c.ghost[d] = dec_.grid[d] > 1;
  }
  return c;
}

bool Halo::owns(double x, double y, double z, const CellGrid& grid) const {
  const double r[3] = {x, y, z};
  for (int d = 0; d < 3; ++d)
    if (dec_.decomposed(d) &&
        dec_.owner_of_cell(d, grid.global_coord(r[d], d)) != dec_.coord[static_cast<std::size_t>(d)])
      return false;
  return true;
}

void Halo::keep_owned(ParticleData& p, const CellGrid& grid) const {
  if (!active()) return;
  std::vector<std::uint32_t> keep;
  for (std::size_t i = 0; i < p.n_local; ++i)
    if (owns(p.x[i], p.y[i], p.z[i], grid)) keep.push_back(static_cast<std::uint32_t>(i));
  p.permute(keep);
}

void Halo::migrate(ParticleData& p, const CellGrid& grid) {
  if (!active()) return;
  Stopwatch sw(seconds_);
  p.resize(p.n_local);
  p.n_ghost = 0;
  const std::size_t kMoveBytes = move_bytes(p);
  std::array<std::vector<int>, 3> owner;
  for (int d = 0; d < 3; ++d)
    for (int g = 0; g < dec_.cells[static_cast<std::size_t>(d)]; ++g)
      owner[static_cast<std::size_t>(d)].push_back(dec_.owner_of_cell(d, g));
  auto owner_along = [&](std::size_t i, int d) {
    return owner[static_cast<std::size_t>(d)][static_cast<std::size_t>(grid.global_coord(coord_array(p, d)[i], d))];
  };
  // A particle moves at most one domain per axis per pass; a second pass (rare: a particle crossed a
  // whole domain since the last migration) follows only if some rank still holds a foreigner.
  const int max_passes = 2 + std::max({dec_.grid[0], dec_.grid[1], dec_.grid[2]});
  for (int pass = 0;; ++pass) {
    for (int d = 0; d < 3; ++d) {
      if (!dec_.decomposed(d)) continue;
      const int np = dec_.grid[static_cast<std::size_t>(d)], me = dec_.coord[static_cast<std::size_t>(d)];
      std::vector<std::byte> out[2];
      std::vector<std::uint32_t> leaving;
      for (std::size_t i = 0; i < p.n_local; ++i) {
        const int k = owner_along(i, d);
        if (k == me) continue;
        // The shorter way round on a periodic axis; a bounded one has only the direct way.
        const int dir = dec_.periodic[static_cast<std::size_t>(d)] ? (((k - me + np) % np) <= np / 2 ? 1 : 0)
                                                                   : (k > me ? 1 : 0);
        out[dir].resize(out[dir].size() + kMoveBytes);
        p.pack<field::kMigrate>(i, out[dir].data() + out[dir].size() - kMoveBytes);
        leaving.push_back(static_cast<std::uint32_t>(i));
      }
      std::vector<std::byte> in[2];
      for (int dir = 0; dir < 2; ++dir) in[dir] = swap(d, dir, 100, out[dir]);
      // Fill the holes from the end (the storage order is rebuilt by the cell sort that follows). Every
      // field moves, so a field that does not migrate keeps its value on the particles that stay.
      constexpr unsigned kAll = ~0u;
      std::size_t end = p.n_local;
      for (auto it = leaving.rbegin(); it != leaving.rend(); ++it) {
        --end;
        if (*it != end) p.copy_to<kAll>(end, p, *it);
      }
      p.n_local = end;
      const std::size_t n0 = p.n_local, m = record_count(in[0], kMoveBytes) + record_count(in[1], kMoveBytes);
      p.resize(n0);  // arrivals start from zeros in the fields that do not migrate
      p.resize(n0 + m);
      p.n_local = n0 + m;
      std::size_t i = n0;
      for (int dir = 0; dir < 2; ++dir)
        for (std::size_t r = 0; r < in[dir].size(); r += kMoveBytes) p.unpack<field::kMigrate>(in[dir].data() + r, i++);
    }
    std::uint64_t foreign = 0;
    for (std::size_t i = 0; i < p.n_local; ++i)
      for (int d = 0; d < 3; ++d)
        if (dec_.decomposed(d) && owner_along(i, d) != dec_.coord[static_cast<std::size_t>(d)]) {
          ++foreign;
          break;
        }
    // The same reduction counts the particles of all ranks, for the lost-particle check.
    std::uint64_t counts[2] = {foreign, p.n_local};
    {
      Stopwatch message(message_seconds_);
      comm_.sum(std::span<std::uint64_t>(counts));
    }
    total_after_migration_ = counts[1];
    p.mark_reordered();
    if (counts[0] == 0) return;
    if (pass + 1 >= max_passes)
      throw std::runtime_error(fmt::format("halo: {} particles still on the wrong rank after {} migration passes",
                                           counts[0], max_passes));
  }
}

void Halo::build_ghosts(ParticleData& p, const CellGrid& grid, std::span<const std::uint32_t> cell_start) {
  const std::size_t n_ghost_cells = grid.num_cells() - grid.num_owned_cells();
  std::vector<std::uint32_t>& ghost_count = ghost_count_;
  ghost_count.assign(n_ghost_cells, 0);
  n_local_ = p.n_local;
  p.resize(p.n_local);
  p.n_ghost = 0;
  slot_.clear();
  if (!active()) return;
  Stopwatch sw(seconds_);
  const auto& own = grid.owned_dims();
  const std::size_t kGhostBytes = ghost_bytes(p);
  GhostRecords ghosts(kGhostBytes);  // in order of arrival, with cell coordinates in this rank's frame
  for (int d = 0; d < 3; ++d) {
    const auto u = static_cast<std::size_t>(d);
    for (int dir = 0; dir < 2; ++dir) send_[u][static_cast<std::size_t>(dir)].clear();
    if (!dec_.decomposed(d)) continue;
    const std::size_t have = ghosts.size();
    GhostRecords out[2] = {GhostRecords(kGhostBytes), GhostRecords(kGhostBytes)};
    for (int dir = 0; dir < 2; ++dir) {
      // The lowest owned layer goes to the neighbour below (its upper ghost layer), the highest above.
      // Locals are sorted by cell, so a layer is a set of cell ranges; earlier ghosts are scanned.
      // Nothing is sent past the end of a bounded axis.
      if (dec_.neighbor(d, dir) == Decomposition::kNoRank) continue;
      const int layer = dir == 0 ? 0 : own[u] - 1;
      auto& list = send_[u][static_cast<std::size_t>(dir)];
      const std::size_t e = (u + 1) % 3, f = (u + 2) % 3;
      for (int b = 0; b < own[f]; ++b)
        for (int a = 0; a < own[e]; ++a) {
          std::array<int, 3> c{};
          c[u] = layer;
          c[e] = a;
          c[f] = b;
          const auto cell = static_cast<std::size_t>(grid.index_of(c[0], c[1], c[2]));
          for (std::uint32_t i = cell_start[cell]; i < cell_start[cell + 1]; ++i) {
            list.push_back(i);
            std::byte* r = out[dir].append();
            for (std::size_t q = 0; q < 3; ++q) set_cell_coord(r, q, static_cast<std::int16_t>(c[q]));
            set_cell_coord(r, 3, 0);
            p.pack<field::kGhost>(i, r + kCellBytes);
          }
        }
      for (std::size_t g = 0; g < have; ++g)
        if (cell_coord(ghosts.at(g), u) == layer) {
          list.push_back(static_cast<std::uint32_t>(n_local_ + g));
          out[dir].append(ghosts.at(g));
        }
    }
    for (int dir = 0; dir < 2; ++dir) {
      const std::vector<std::byte> in = swap(d, dir, 200, out[dir].bytes());
      const std::size_t m = record_count(in, kGhostBytes);
      recv_begin_[u][static_cast<std::size_t>(dir)] = n_local_ + ghosts.size();
      recv_count_[u][static_cast<std::size_t>(dir)] = m;
      // What the neighbour above sent (its lowest layer) is this rank's upper ghost layer, and vice versa.
      const std::int16_t layer = static_cast<std::int16_t>(dir == 0 ? own[u] : -1);
      for (std::size_t k = 0; k < m; ++k) {
        std::byte* r = ghosts.append();
        std::memcpy(r, in.data() + k * kGhostBytes, kGhostBytes);
        set_cell_coord(r, u, layer);
      }
    }
  }
  // Sort ghosts by cell (counting sort, stable) so that each ghost cell is one contiguous range.
  const std::size_t ng = ghosts.size();
  const std::size_t owned = grid.num_owned_cells();
  std::vector<std::uint32_t> cell(ng);
  for (std::size_t g = 0; g < ng; ++g) {
    const std::byte* r = ghosts.at(g);
    const int idx = grid.index_of(cell_coord(r, 0), cell_coord(r, 1), cell_coord(r, 2));
    if (idx < static_cast<int>(owned)) throw std::runtime_error("halo: a ghost landed in an owned cell");
    cell[g] = static_cast<std::uint32_t>(static_cast<std::size_t>(idx) - owned);
    ++ghost_count[cell[g]];
  }
  std::vector<std::size_t> fill(n_ghost_cells + 1, 0);
  for (std::size_t c = 0; c < n_ghost_cells; ++c) fill[c + 1] = fill[c] + ghost_count[c];
  slot_.resize(ng);
  for (std::size_t g = 0; g < ng; ++g) slot_[g] = static_cast<std::uint32_t>(n_local_ + fill[cell[g]]++);
  p.resize(n_local_ + ng);
  p.n_ghost = ng;
  for (std::size_t g = 0; g < ng; ++g) p.unpack<field::kGhost>(ghosts.at(g) + kCellBytes, slot_[g]);
  p.mark_reordered();
}

template <class Pack, class Unpack>
void Halo::forward(std::size_t record_bytes, int tag_base, Pack&& pack, Unpack&& unpack) {
  // Along the axes in the order of the build, so ghosts forwarded by an intermediate rank carry the
  // values that rank has just received.
  for (int d = 0; d < 3; ++d) {
    const auto u = static_cast<std::size_t>(d);
    if (!dec_.decomposed(d)) continue;
    for (int dir = 0; dir < 2; ++dir) {
      const auto& list = send_[u][static_cast<std::size_t>(dir)];
      std::vector<std::byte> out(record_bytes * list.size());
      for (std::size_t k = 0; k < list.size(); ++k) pack(storage_of(list[k]), out.data() + k * record_bytes);
      const std::vector<std::byte> in = swap(d, dir, tag_base, out);
      const std::size_t b = recv_begin_[u][static_cast<std::size_t>(dir)], m = recv_count_[u][static_cast<std::size_t>(dir)];
      if (in.size() != record_bytes * m) throw std::runtime_error("halo: ghost refresh size mismatch");
      for (std::size_t k = 0; k < m; ++k) unpack(in.data() + k * record_bytes, storage_of(b + k));
    }
  }
}

void Halo::update_ghosts(ParticleData& p) {
  if (!active()) return;
  Stopwatch sw(seconds_);
  forward(
      refresh_bytes(p), 300, [&](std::size_t s, std::byte* out) { p.pack<field::kRefresh>(s, out); },
      [&](const std::byte* in, std::size_t s) { p.unpack<field::kRefresh>(in, s); });
}

void Halo::forward_field(ParticleData& p, std::span<double> f) {
  if (!active()) return;
  if (f.size() < p.size())
    throw std::runtime_error(fmt::format("halo: forward_field got {} values for {} particles", f.size(), p.size()));
  Stopwatch sw(seconds_);
  forward(
      sizeof(double), 500, [&](std::size_t s, std::byte* out) { std::memcpy(out, &f[s], sizeof(double)); },
      [&](const std::byte* in, std::size_t s) { std::memcpy(&f[s], in, sizeof(double)); });
}

void Halo::reverse_sums(std::int64_t* v, int components, const ParticleData& p) {
  if (!active()) return;
  Stopwatch sw(seconds_);
  const auto nc = static_cast<std::size_t>(components);
  for (int d = 2; d >= 0; --d) {
    const auto u = static_cast<std::size_t>(d);
    if (!dec_.decomposed(d)) continue;
    for (int dir = 0; dir < 2; ++dir) {
      const std::size_t b = recv_begin_[u][static_cast<std::size_t>(dir)], m = recv_count_[u][static_cast<std::size_t>(dir)];
      std::vector<std::int64_t> out(nc * m);
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t s = storage_of(b + k);
        for (std::size_t q = 0; q < nc; ++q) out[nc * k + q] = v[nc * s + q];
      }
      // Back along the way the ghosts came: to the rank they were received from.
      const std::vector<std::int64_t> in = records_from<std::int64_t>(
          swap(d, 1 - dir, 400, as_bytes_of(out)));
      const auto& list = send_[u][static_cast<std::size_t>(dir)];
      if (in.size() != nc * list.size()) throw std::runtime_error("halo: reverse sum size mismatch");
      for (std::size_t k = 0; k < list.size(); ++k) {
        const std::size_t s = storage_of(list[k]);
        for (std::size_t q = 0; q < nc; ++q) v[nc * s + q] += in[nc * k + q];
      }
    }
  }
  (void)p;  // storage indices come from the last build_ghosts
}

}  // namespace mesodpd

namespace mesodpd {

void gather_by_id(const ParticleData& p, const Comm& comm, std::uint64_t expected, ParticleData& all) {
  // The gathered copy holds the same optional fields.
  all.enable_mask(p.optional_mask());
  const std::size_t kMoveBytes = move_bytes(p);
  // Places records (in any order) at their position in id order; ids must be distinct.
  auto place = [&](std::size_t n, auto&& id_of, auto&& put) {
    if (n != expected)
      throw std::runtime_error(fmt::format("particles lost or duplicated: {} expected, {} found on {} rank(s)",
                                           expected, n, comm.size()));
    all.resize(n);
    all.n_local = n;
    all.n_ghost = 0;
    if (n == 0) return;
    std::uint32_t min_id = id_of(0), max_id = 0;
    for (std::size_t k = 0; k < n; ++k) {
      min_id = std::min(min_id, id_of(k));
      max_id = std::max(max_id, id_of(k));
    }
    if (max_id - min_id == n - 1) {
      // Consecutive ids (the usual case, 1 .. N): each record goes to id - min_id.
      std::vector<std::uint8_t> seen(n, 0);
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t at = id_of(k) - min_id;
        if (seen[at]) throw std::runtime_error(fmt::format("particle id {} appears twice", id_of(k)));
        seen[at] = 1;
        put(k, at);
      }
      return;
    }
    std::vector<std::uint32_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = static_cast<std::uint32_t>(k);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return id_of(a) < id_of(b); });
    for (std::size_t k = 0; k < n; ++k) {
      if (k > 0 && id_of(order[k]) == id_of(order[k - 1]))
        throw std::runtime_error(fmt::format("particle id {} appears twice", id_of(order[k])));
      put(order[k], k);
    }
  };
  if (!comm.distributed()) {
    // One rank: copy straight into id order, no message records.
    place(
        p.n_local, [&](std::size_t k) { return p.id[k]; },
        [&](std::size_t from, std::size_t to) { p.copy_to<field::kMigrate>(from, all, to); });
    return;
  }
  std::vector<std::byte> mine(p.n_local * kMoveBytes);
  for (std::size_t i = 0; i < p.n_local; ++i) p.pack<field::kMigrate>(i, mine.data() + i * kMoveBytes);
  const std::vector<std::byte> bytes = comm.gather(mine);
  comm.on_root([&] {
    const std::size_t n = record_count(bytes, kMoveBytes);
    // The id is the first field of the list, so it leads every record.
    static_assert(std::string_view(ParticleData::fields()[0].name) == "id" &&
                  (ParticleData::fields()[0].flags & field::kMigrate));
    auto id_of = [&](std::size_t k) {
      std::uint32_t id;
      std::memcpy(&id, bytes.data() + k * kMoveBytes, sizeof id);
      return id;
    };
    place(n, id_of, [&](std::size_t from, std::size_t to) { all.unpack<field::kMigrate>(bytes.data() + from * kMoveBytes, to); });
  });
}

ParticleData gather_by_id(const ParticleData& p, const Comm& comm, std::uint64_t expected) {
  ParticleData all;
  gather_by_id(p, comm, expected, all);
  return all;
}

}  // namespace mesodpd
