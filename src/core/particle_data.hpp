// Structure-of-arrays particle storage: local particles in [0, n_local), ghost copies after them.
// One list (MESODPD_PARTICLE_FIELDS) names every per-particle array and what follows it.
#pragma once
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <vector>

namespace mesodpd {

// What a per-particle field takes part in, besides resize and sort/permute (which every field follows).
namespace field {
inline constexpr unsigned kMigrate = 1u << 0;     // travels with its particle to a new owner rank, and
                                                  // is gathered by gather_by_id (output, checkpoints)
inline constexpr unsigned kGhost = 1u << 1;       // copied to ghost copies when ghosts are built
inline constexpr unsigned kRefresh = 1u << 2;     // also refreshed on ghosts between rebuilds (update_ghosts)
inline constexpr unsigned kCheckpoint = 1u << 3;  // stored in state checkpoints (needs kMigrate)
inline constexpr unsigned kFrame = 1u << 4;       // offered to trajectory frames (io/frame.hpp)
inline constexpr unsigned kForce = 1u << 5;       // recomputed by the force stage before anything reads
                                                  // it: permute(Forces::Discard) leaves it unordered
inline constexpr unsigned kOptional = 1u << 6;    // held only where a model enables it (ParticleData::enable):
                                                  // until then its array stays empty and every path above
                                                  // (resize, permute, records, checkpoints, frames) skips it,
                                                  // so a model's fields cost nothing in runs without it
}  // namespace field

// THE list of per-particle fields: X(element type, member name, flags). Adding a field is one line
// here plus its uses; resize, permute, migration, ghost exchange (when flagged), gather_by_id,
// checkpoints and frames follow from it (recipe in docs/architecture.md). A build may append
// fields of its own through MESODPD_EXTRA_PARTICLE_FIELDS (the tests do, to prove that a new field
// follows every path).
#ifndef MESODPD_EXTRA_PARTICLE_FIELDS
#define MESODPD_EXTRA_PARTICLE_FIELDS(X)
#endif
#define MESODPD_PARTICLE_FIELDS(X)                                                                           \
  /* global id, unique and stable for the whole run */                                                      \
  X(std::uint32_t, id, field::kMigrate | field::kGhost | field::kCheckpoint | field::kFrame)                \
  /* index into the species table */                                                                        \
  X(std::int32_t, species, field::kMigrate | field::kGhost | field::kCheckpoint | field::kFrame)            \
  /* wrapped positions in [0, L) */                                                                         \
  X(double, x, field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint | field::kFrame)       \
  X(double, y, field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint | field::kFrame)       \
  X(double, z, field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint | field::kFrame)       \
  /* velocities (during the force stage: the predicted velocity) */                                         \
  X(double, vx, field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint | field::kFrame)      \
  X(double, vy, field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint | field::kFrame)      \
  X(double, vz, field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint | field::kFrame)      \
  /* total force of the last force evaluation (modified velocity-Verlet reads it across steps) */           \
  X(double, fx, field::kMigrate | field::kCheckpoint | field::kFrame | field::kForce)                         \
  X(double, fy, field::kMigrate | field::kCheckpoint | field::kFrame | field::kForce)                         \
  X(double, fz, field::kMigrate | field::kCheckpoint | field::kFrame | field::kForce)                         \
  /* integrator scratch: half-step velocity of modified velocity-Verlet */                                  \
  X(double, hx, field::kMigrate)                                                                             \
  X(double, hy, field::kMigrate)                                                                             \
  X(double, hz, field::kMigrate)                                                                             \
  /* periodic image counters: unwrapped x = x + ix * Lx */                                                  \
  X(std::int32_t, ix, field::kMigrate | field::kCheckpoint | field::kFrame)                                  \
  X(std::int32_t, iy, field::kMigrate | field::kCheckpoint | field::kFrame)                                  \
  X(std::int32_t, iz, field::kMigrate | field::kCheckpoint | field::kFrame)                                  \
  /* molecule id (1, 2, ...; 0 for a particle in no molecule), the LAMMPS dump's `mol` column */            \
  X(std::int32_t, mol, field::kMigrate | field::kCheckpoint | field::kFrame)                                 \
  /* solid body of a frozen wall particle: [[solid]] index + 1, 0 for a mobile particle (ghosts carry it  \
     so that the pair loop skips frozen-frozen pairs) */                                                   \
  X(std::int32_t, body, field::kMigrate | field::kGhost | field::kCheckpoint | field::kFrame)                \
  /* optional (enabled by the model that uses them) --------------------------------------------------- */ \
  /* energy-conserving DPD (physics/edpd_pair.hpp): the internal temperature T_i and its rate dT_i/dt of   \
     the last force evaluation, the heat flux over C_v (the modified velocity-Verlet reads it across steps) */ \
  X(double, temp, field::kOptional | field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint |  \
                      field::kFrame)                                                                          \
  X(double, temp_rate, field::kOptional | field::kMigrate | field::kCheckpoint | field::kFrame | field::kForce) \
  /* transport DPD (physics/tdpd_pair.hpp): up to 4 solute concentrations C_i^k and their rates dC/dt */     \
  MESODPD_SOLUTE_FIELDS(X, 1)                                                                                 \
  MESODPD_SOLUTE_FIELDS(X, 2)                                                                                 \
  MESODPD_SOLUTE_FIELDS(X, 3)                                                                                 \
  MESODPD_SOLUTE_FIELDS(X, 4)                                                                                 \
  /* single-particle DPD (physics/spdpd_pair.hpp): the angular velocity Omega_i and its rate dOmega_i/dt =   \
     T_i / I of the last force evaluation (read across steps like temp_rate) */                             \
  MESODPD_SPIN_FIELDS(X, x)                                                                                   \
  MESODPD_SPIN_FIELDS(X, y)                                                                                   \
  MESODPD_SPIN_FIELDS(X, z)                                                                                   \
  MESODPD_EXTRA_PARTICLE_FIELDS(X)
// One solute's concentration and rate (optional; the rate read across steps like temp_rate).
#define MESODPD_SOLUTE_FIELDS(X, k)                                                                          \
  X(double, conc##k, field::kOptional | field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint | \
                         field::kFrame)                                                                       \
  X(double, conc_rate##k, field::kOptional | field::kMigrate | field::kCheckpoint | field::kFrame | field::kForce)

// One component of the angular velocity and of its rate (optional).
#define MESODPD_SPIN_FIELDS(X, a)                                                                            \
  X(double, omega_##a, field::kOptional | field::kMigrate | field::kGhost | field::kRefresh | field::kCheckpoint | \
                           field::kFrame)                                                                     \
  X(double, omega_rate_##a, field::kOptional | field::kMigrate | field::kCheckpoint | field::kFrame | field::kForce)

// Name, flags and element type of one field, for code that handles fields by name (checkpoints).
struct FieldInfo {
  const char* name;
  unsigned flags;
  char kind;               // 'u' unsigned integer, 'i' signed integer, 'f' floating point
  std::size_t elem_bytes;  // sizeof the element type
};

template <class T>
constexpr char field_kind() {
  static_assert(std::is_arithmetic_v<T>, "per-particle fields hold arithmetic values");
  return std::is_floating_point_v<T> ? 'f' : (std::is_signed_v<T> ? 'i' : 'u');
}

// Owns every per-particle array. Code that reorders particles goes through permute(), so no array can
// be forgotten. Ghosts (copies of particles owned elsewhere, for domain decomposition) occupy
// [n_local, n_local + n_ghost); a single-domain periodic run needs none, because pair displacements
// use the minimum image (core/box.hpp).
struct ParticleData {
  std::size_t n_local = 0;
  std::size_t n_ghost = 0;

  // One public std::vector per field (x, y, z, vx, ..., id, species): the pair loop takes .data().
#define MESODPD_DECLARE_FIELD(T, name, flags) std::vector<T> name;
  MESODPD_PARTICLE_FIELDS(MESODPD_DECLARE_FIELD)
#undef MESODPD_DECLARE_FIELD

#define MESODPD_COUNT_FIELD(T, name, flags) +1
  static constexpr std::size_t kFieldCount = 0 MESODPD_PARTICLE_FIELDS(MESODPD_COUNT_FIELD);
#undef MESODPD_COUNT_FIELD
  // Every field's name, flags and element type, in list order (optional ones included, enabled or not).
  static constexpr std::array<FieldInfo, kFieldCount> fields() {
    return std::array<FieldInfo, kFieldCount>{
#define MESODPD_FIELD_INFO(T, name, flags) FieldInfo{#name, (flags), field_kind<T>(), sizeof(T)},
        MESODPD_PARTICLE_FIELDS(MESODPD_FIELD_INFO)
#undef MESODPD_FIELD_INFO
    };
  }
  // The position of a field in the list, by name (kFieldCount if there is none of that name).
  static constexpr std::size_t field_index(std::string_view name) {
    for (std::size_t k = 0; k < kFieldCount; ++k)
      if (name == fields()[k].name) return k;
    return kFieldCount;
  }

  // Optional fields (field::kOptional) are held only once enabled: enable() sizes the array to the
  // stored particles (zeros) and from then on every path treats it as any other field. A set of enabled
  // fields as a bit mask over the list's indices, for copies that must hold the same fields.
  bool enabled(std::size_t index) const {
    return !(fields()[index].flags & field::kOptional) || ((optional_on_ >> index) & 1u) != 0;
  }
  bool enabled(std::string_view name) const { return enabled(field_index(name)); }
  void enable(std::string_view name);
  std::uint64_t optional_mask() const { return optional_on_; }
  void enable_mask(std::uint64_t mask);
  // A held field of doubles by name ("temp", "conc1"), or nullptr where there is none of that name and
  // type or it is not enabled: for code that is told its fields by name (a law's kScalarFields).
  std::vector<double>* doubles(std::string_view name);
  const std::vector<double>* doubles(std::string_view name) const {
    return const_cast<ParticleData*>(this)->doubles(name);
  }

  // Calls f(info, vector) for every field that is held (the fixed ones and the enabled optional ones),
  // in list order.
  template <class F>
  void for_each_field(F&& f) {
    std::size_t index = 0;
#define MESODPD_VISIT_FIELD(T, name, flags) \
  if (enabled(index++)) f(FieldInfo{#name, (flags), field_kind<T>(), sizeof(T)}, name);
    MESODPD_PARTICLE_FIELDS(MESODPD_VISIT_FIELD)
#undef MESODPD_VISIT_FIELD
  }
  template <class F>
  void for_each_field(F&& f) const {
    std::size_t index = 0;
#define MESODPD_VISIT_FIELD(T, name, flags) \
  if (enabled(index++)) f(FieldInfo{#name, (flags), field_kind<T>(), sizeof(T)}, name);
    MESODPD_PARTICLE_FIELDS(MESODPD_VISIT_FIELD)
#undef MESODPD_VISIT_FIELD
  }

  std::size_t size() const { return n_local + n_ghost; }

  // Growing keeps 1/8 headroom rather than the standard library's doubling: appending ghosts (a few
  // per cent of the locals) must not double the memory of every array.
  void resize(std::size_t n) {
    const std::size_t room = n + n / 8;
    for_each_field([&](const FieldInfo&, auto& v) {
      if (n > v.capacity()) v.reserve(room);
      v.resize(n, 0);
    });
    generation_ = next_generation();
  }

  // Reorder local particles so that new index k holds old index order[k]; ghosts are dropped. The
  // arrays keep room for `capacity` particles (ghosts to be appended without a reallocation). With
  // `forces` = Forces::Discard the fields flagged kForce are resized but not reordered (their contents
  // are then meaningless): for callers that recompute every force before reading one, which saves 3
  // of the 17 arrays of memory traffic.
  enum class Forces { Keep, Discard };
  void permute(const std::vector<std::uint32_t>& order, std::size_t capacity = 0, Forces forces = Forces::Keep);

  // Bytes of one packed record of the held fields whose flags include any bit of Mask.
  template <unsigned Mask>
  std::size_t record_bytes() const {
    std::size_t b = 0;
    for (std::size_t k = 0; k < kFieldCount; ++k)
      if ((fields()[k].flags & Mask) && enabled(k)) b += fields()[k].elem_bytes;
    return b;
  }
  // Packs particle i's fields selected by Mask (list order, no padding) into out[0, record_bytes<Mask>()).
  template <unsigned Mask>
  void pack(std::size_t i, std::byte* out) const {
    for_each_field([&](const FieldInfo& f, const auto& v) {
      if (!(f.flags & Mask)) return;
      std::memcpy(out, &v[i], sizeof(v[i]));
      out += sizeof(v[i]);
    });
  }
  // The inverse of pack: writes the selected fields of particle i from a record.
  template <unsigned Mask>
  void unpack(const std::byte* in, std::size_t i) {
    for_each_field([&](const FieldInfo& f, auto& v) {
      if (!(f.flags & Mask)) return;
      std::memcpy(&v[i], in, sizeof(v[i]));
      in += sizeof(v[i]);
    });
  }
  // Copies the selected fields of particle `from` to particle `to` of `dst` (which may be *this); an
  // optional field only where both hold it.
  template <unsigned Mask>
  void copy_to(std::size_t from, ParticleData& dst, std::size_t to) const {
#define MESODPD_COPY_FIELD(T, name, flags)                                            \
  if constexpr (((flags) & Mask) != 0) {                                              \
    if constexpr (((flags) & field::kOptional) != 0) {                                \
      if (!dst.name.empty() && !name.empty()) dst.name[to] = name[from];              \
    } else {                                                                          \
      dst.name[to] = name[from];                                                      \
    }                                                                                 \
  }
    MESODPD_PARTICLE_FIELDS(MESODPD_COPY_FIELD)
#undef MESODPD_COPY_FIELD
  }

  // Changed by every resize and permute, and by mark_reordered(): code that caches storage indices
  // (IdMap, core/id_map.hpp) compares it to know when they went stale. Values are unique in the
  // process, so a ParticleData replaced by another (a checkpoint load) never repeats a value.
  std::uint64_t generation() const { return generation_; }
  // For code that moves particles or changes ids by writing the arrays directly; call it after the
  // writes (migration, ghost construction, reading a file).
  void mark_reordered() { generation_ = next_generation(); }
  // The order of the last permute() if that is the only change since generation `g` (nothing resized,
  // reordered or appended after it), else nullptr: storage index k now holds what index order[k] held
  // at `g`. Lets caches of storage indices follow a sort instead of rebuilding from ids.
  const std::vector<std::uint32_t>* permutation_since(std::uint64_t g) const {
    return permuted_from_ == g && permuted_to_ == generation_ ? &last_order_ : nullptr;
  }

 private:
  // Spare buffers that permute() gathers into and swaps with, one per element type, kept so that
  // sorting every step does not allocate (a fresh allocation of this size costs page faults, which do
  // not parallelise). A field of a type missing here is a compile error in spare<T>().
  std::tuple<std::vector<double>, std::vector<float>, std::vector<std::int32_t>, std::vector<std::uint32_t>,
             std::vector<std::int64_t>, std::vector<std::uint64_t>, std::vector<std::int8_t>,
             std::vector<std::uint8_t>>
      spares_;
  template <class T>
  std::vector<T>& spare() {
    return std::get<std::vector<T>>(spares_);
  }
  static std::uint64_t next_generation() {
    static std::atomic<std::uint64_t> counter{0};
    return ++counter;
  }
  std::uint64_t generation_ = next_generation();
  std::uint64_t optional_on_ = 0;  // bit k: optional field k is enabled
  // The last permute(): its order and the generations before and after it.
  std::vector<std::uint32_t> last_order_;
  std::uint64_t permuted_from_ = 0, permuted_to_ = 0;
};

// All flags used by a field of the list must be consistent: a checkpointed field is gathered on the
// root with the migrating fields, and a refreshed ghost field must exist on ghosts.
static_assert([] {
  for (const FieldInfo& f : ParticleData::fields()) {
    if ((f.flags & field::kCheckpoint) && !(f.flags & field::kMigrate)) return false;
    if ((f.flags & field::kRefresh) && !(f.flags & field::kGhost)) return false;
  }
  return ParticleData::kFieldCount <= 64;
}(), "particle field list: kCheckpoint needs kMigrate and kRefresh needs kGhost (and at most 64 fields)");

}  // namespace mesodpd
