// Migration, ghost construction, ghost refresh and reverse force communication.
#include "parallel/halo.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace mesodpd {

namespace {

// Everything a particle carries when it changes owner.
struct MoveRecord {
  double v[12];  // x y z, vx vy vz, fx fy fz, hx hy hz
  std::uint32_t id;
  std::int32_t species, ix, iy, iz;
};

// What a pair force reads from a ghost, plus its cell coordinates in the receiver's grid frame.
struct GhostRecord {
  double x, y, z, vx, vy, vz;
  std::uint32_t id;
  std::int32_t species;
  std::int16_t c[3];
  std::int16_t pad;
};

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

int tag(int base, int d, int dir) { return base + 2 * d + dir; }

MoveRecord pack_particle(const ParticleData& p, std::size_t i) {
  MoveRecord r{};
  const std::vector<double>* arrays[12] = {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.hx, &p.hy, &p.hz};
  for (int q = 0; q < 12; ++q) r.v[q] = (*arrays[q])[i];
  r.id = p.id[i];
  r.species = p.species[i];
  r.ix = p.ix[i];
  r.iy = p.iy[i];
  r.iz = p.iz[i];
  return r;
}

void unpack_particle(const MoveRecord& r, ParticleData& p, std::size_t i) {
  std::vector<double>* arrays[12] = {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.hx, &p.hy, &p.hz};
  for (int q = 0; q < 12; ++q) (*arrays[q])[i] = r.v[q];
  p.id[i] = r.id;
  p.species[i] = r.species;
  p.ix[i] = r.ix;
  p.iy[i] = r.iy;
  p.iz[i] = r.iz;
}

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
      std::vector<MoveRecord> out[2];
      std::vector<std::uint32_t> leaving;
      for (std::size_t i = 0; i < p.n_local; ++i) {
        const int k = owner_along(i, d);
        if (k == me) continue;
        // The shorter way round on a periodic axis; a bounded one has only the direct way.
        const int dir = dec_.periodic[static_cast<std::size_t>(d)] ? (((k - me + np) % np) <= np / 2 ? 1 : 0)
                                                                   : (k > me ? 1 : 0);
        out[dir].push_back(pack_particle(p, i));
        leaving.push_back(static_cast<std::uint32_t>(i));
      }
      std::vector<MoveRecord> in[2];
      for (int dir = 0; dir < 2; ++dir)
        in[dir] = records_from<MoveRecord>(
            swap(d, dir, 100, as_bytes_of(out[dir])));
      // Fill the holes from the end (the storage order is rebuilt by the cell sort that follows).
      std::size_t end = p.n_local;
      for (auto it = leaving.rbegin(); it != leaving.rend(); ++it) {
        --end;
        if (*it != end) unpack_particle(pack_particle(p, end), p, *it);
      }
      p.n_local = end;
      const std::size_t n0 = p.n_local, m = in[0].size() + in[1].size();
      p.resize(n0 + m);
      p.n_local = n0 + m;
      std::size_t i = n0;
      for (int dir = 0; dir < 2; ++dir)
        for (const MoveRecord& r : in[dir]) unpack_particle(r, p, i++);
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
  std::vector<GhostRecord> ghosts;  // in order of arrival, with cell coordinates in this rank's frame
  for (int d = 0; d < 3; ++d) {
    const auto u = static_cast<std::size_t>(d);
    for (int dir = 0; dir < 2; ++dir) send_[u][static_cast<std::size_t>(dir)].clear();
    if (!dec_.decomposed(d)) continue;
    const std::size_t have = ghosts.size();
    std::vector<GhostRecord> out[2];
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
            out[dir].push_back(GhostRecord{p.x[i], p.y[i], p.z[i], p.vx[i], p.vy[i], p.vz[i], p.id[i], p.species[i],
                                           {static_cast<std::int16_t>(c[0]), static_cast<std::int16_t>(c[1]),
                                            static_cast<std::int16_t>(c[2])},
                                           0});
          }
        }
      for (std::size_t g = 0; g < have; ++g)
        if (ghosts[g].c[u] == layer) {
          list.push_back(static_cast<std::uint32_t>(n_local_ + g));
          out[dir].push_back(ghosts[g]);
        }
    }
    for (int dir = 0; dir < 2; ++dir) {
      std::vector<GhostRecord> in = records_from<GhostRecord>(
          swap(d, dir, 200, as_bytes_of(out[dir])));
      recv_begin_[u][static_cast<std::size_t>(dir)] = n_local_ + ghosts.size();
      recv_count_[u][static_cast<std::size_t>(dir)] = in.size();
      // What the neighbour above sent (its lowest layer) is this rank's upper ghost layer, and vice versa.
      const std::int16_t layer = static_cast<std::int16_t>(dir == 0 ? own[u] : -1);
      for (GhostRecord& r : in) {
        r.c[u] = layer;
        ghosts.push_back(r);
      }
    }
  }
  // Sort ghosts by cell (counting sort, stable) so that each ghost cell is one contiguous range.
  const std::size_t ng = ghosts.size();
  const std::size_t owned = grid.num_owned_cells();
  std::vector<std::uint32_t> cell(ng);
  for (std::size_t g = 0; g < ng; ++g) {
    const auto& c = ghosts[g].c;
    const int idx = grid.index_of(c[0], c[1], c[2]);
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
  for (std::size_t g = 0; g < ng; ++g) {
    const std::size_t s = slot_[g];
    const GhostRecord& r = ghosts[g];
    p.x[s] = r.x;
    p.y[s] = r.y;
    p.z[s] = r.z;
    p.vx[s] = r.vx;
    p.vy[s] = r.vy;
    p.vz[s] = r.vz;
    p.id[s] = r.id;
    p.species[s] = r.species;
  }
}

void Halo::update_ghosts(ParticleData& p) {
  if (!active()) return;
  Stopwatch sw(seconds_);
  for (int d = 0; d < 3; ++d) {
    const auto u = static_cast<std::size_t>(d);
    if (!dec_.decomposed(d)) continue;
    for (int dir = 0; dir < 2; ++dir) {
      const auto& list = send_[u][static_cast<std::size_t>(dir)];
      std::vector<double> out(6 * list.size());
      for (std::size_t k = 0; k < list.size(); ++k) {
        const std::size_t s = storage_of(list[k]);
        double* o = &out[6 * k];
        o[0] = p.x[s];
        o[1] = p.y[s];
        o[2] = p.z[s];
        o[3] = p.vx[s];
        o[4] = p.vy[s];
        o[5] = p.vz[s];
      }
      const std::vector<double> in = records_from<double>(
          swap(d, dir, 300, as_bytes_of(out)));
      const std::size_t b = recv_begin_[u][static_cast<std::size_t>(dir)], m = recv_count_[u][static_cast<std::size_t>(dir)];
      if (in.size() != 6 * m) throw std::runtime_error("halo: ghost refresh size mismatch");
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t s = storage_of(b + k);
        const double* v = &in[6 * k];
        p.x[s] = v[0];
        p.y[s] = v[1];
        p.z[s] = v[2];
        p.vx[s] = v[3];
        p.vy[s] = v[4];
        p.vz[s] = v[5];
      }
    }
  }
}

void Halo::reverse_forces(std::int64_t* f3, const ParticleData& p) {
  if (!active()) return;
  Stopwatch sw(seconds_);
  for (int d = 2; d >= 0; --d) {
    const auto u = static_cast<std::size_t>(d);
    if (!dec_.decomposed(d)) continue;
    for (int dir = 0; dir < 2; ++dir) {
      const std::size_t b = recv_begin_[u][static_cast<std::size_t>(dir)], m = recv_count_[u][static_cast<std::size_t>(dir)];
      std::vector<std::int64_t> out(3 * m);
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t s = storage_of(b + k);
        for (int q = 0; q < 3; ++q) out[3 * k + static_cast<std::size_t>(q)] = f3[3 * s + static_cast<std::size_t>(q)];
      }
      // Back along the way the ghosts came: to the rank they were received from.
      const std::vector<std::int64_t> in = records_from<std::int64_t>(
          swap(d, 1 - dir, 400, as_bytes_of(out)));
      const auto& list = send_[u][static_cast<std::size_t>(dir)];
      if (in.size() != 3 * list.size()) throw std::runtime_error("halo: reverse force size mismatch");
      for (std::size_t k = 0; k < list.size(); ++k) {
        const std::size_t s = storage_of(list[k]);
        for (int q = 0; q < 3; ++q) f3[3 * s + static_cast<std::size_t>(q)] += in[3 * k + static_cast<std::size_t>(q)];
      }
    }
  }
  (void)p;  // storage indices come from the last build_ghosts
}

}  // namespace mesodpd

namespace mesodpd {

void gather_by_id(const ParticleData& p, const Comm& comm, std::uint64_t expected, ParticleData& all) {
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
        [&](std::size_t from, std::size_t to) { unpack_particle(pack_particle(p, from), all, to); });
    return;
  }
  std::vector<MoveRecord> mine(p.n_local);
  for (std::size_t i = 0; i < p.n_local; ++i) mine[i] = pack_particle(p, i);
  const std::vector<std::byte> bytes = comm.gather(as_bytes_of(mine));
  comm.on_root([&] {
    const std::vector<MoveRecord> recs = records_from<MoveRecord>(bytes);
    place(
        recs.size(), [&](std::size_t k) { return recs[k].id; },
        [&](std::size_t from, std::size_t to) { unpack_particle(recs[from], all, to); });
  });
}

ParticleData gather_by_id(const ParticleData& p, const Comm& comm, std::uint64_t expected) {
  ParticleData all;
  gather_by_id(p, comm, expected, all);
  return all;
}

}  // namespace mesodpd
