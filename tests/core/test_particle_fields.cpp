// The particle field list: every field follows resize, permute and records; checkpoints store the
// fields flagged for them and refuse other payload versions; the id -> index map.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <random>
#include <set>
#include <string>

#include "core/id_map.hpp"
#include "core/particle_data.hpp"
#include "io/byte_buffer.hpp"
#include "io/checkpoint_file.hpp"
#include "io/state_checkpoint.hpp"

namespace fs = std::filesystem;
using namespace mesodpd;

namespace {

// A value for field number `k` of the particle with id `id`, distinct for every (k, id) pair and
// exactly representable in every element type of the list.
template <class T>
T value_for(std::size_t k, std::uint32_t id) {
  return static_cast<T>(static_cast<long long>(1000 * k + id % 997));
}

// Every optional field of the list enabled (optional_mask() of such a ParticleData).
std::uint64_t every_optional() {
  std::uint64_t mask = 0;
  for (std::size_t k = 0; k < ParticleData::kFieldCount; ++k)
    if (ParticleData::fields()[k].flags & field::kOptional) mask |= std::uint64_t{1} << k;
  return mask;
}

// n particles with ids 1..n in a shuffled storage order and every field (the optional ones enabled)
// set from (field, id).
ParticleData shuffled(std::size_t n, unsigned seed) {
  ParticleData p;
  p.enable_mask(every_optional());
  p.resize(n);
  p.n_local = n;
  std::vector<std::uint32_t> ids(n);
  std::iota(ids.begin(), ids.end(), 1u);
  std::shuffle(ids.begin(), ids.end(), std::mt19937(seed));
  p.id = ids;
  std::size_t k = 0;
  p.for_each_field([&](const FieldInfo& f, auto& v) {
    using T = typename std::remove_reference_t<decltype(v)>::value_type;
    if (std::string(f.name) != "id")
      for (std::size_t i = 0; i < n; ++i) v[i] = value_for<T>(k, p.id[i]);
    ++k;
  });
  return p;
}

// Every field of every particle holds the value for its id (fields in `mask`; others must be zero).
void expect_consistent(const ParticleData& p, std::size_t n, unsigned mask = ~0u) {
  std::size_t k = 0;
  p.for_each_field([&](const FieldInfo& f, const auto& v) {
    using T = typename std::remove_reference_t<decltype(v)>::value_type;
    ASSERT_GE(v.size(), n) << f.name;
    if (std::string(f.name) != "id") {
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_EQ(v[i], (f.flags & mask) ? value_for<T>(k, p.id[i]) : T{0}) << f.name << " of id " << p.id[i];
    }
    ++k;
  });
}

fs::path temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_particle_fields";
  fs::create_directories(dir);
  return dir / name;
}

}  // namespace

TEST(ParticleFields, TheListNamesEveryPublicArrayOnce) {
  // The arrays the pair loop and the integrator use by name are in the list, each once.
  std::set<std::string> names;
  for (const FieldInfo& f : ParticleData::fields()) EXPECT_TRUE(names.insert(f.name).second) << f.name;
  for (const char* n : {"id", "species", "x", "y", "z", "vx", "vy", "vz", "fx", "fy", "fz", "hx", "hy", "hz", "ix",
                        "iy", "iz"})
    EXPECT_EQ(names.count(n), 1u) << n;
  EXPECT_STREQ(ParticleData::fields()[0].name, "id");  // records lead with the id (gather_by_id)
}

TEST(ParticleFields, ResizeGrowsEveryFieldAndPermuteMovesEveryField) {
  ParticleData p = shuffled(500, 1);
  // Sort by id: the permutation a cell sort would apply, in general.
  std::vector<std::uint32_t> order(p.n_local);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return p.id[a] < p.id[b]; });
  const auto g0 = p.generation();
  p.permute(order, 600);
  EXPECT_NE(p.generation(), g0);
  for (std::size_t i = 0; i < p.n_local; ++i) ASSERT_EQ(p.id[i], i + 1);
  expect_consistent(p, p.n_local);
  p.for_each_field([&](const FieldInfo& f, const auto& v) { EXPECT_GE(v.capacity(), 600u) << f.name; });
  // Discarding forces reorders everything else.
  std::iota(order.rbegin(), order.rend(), 0u);  // reverse the (now sorted) storage
  p.permute(order, 0, ParticleData::Forces::Discard);
  EXPECT_EQ(p.id.front(), 500u);
  std::size_t k = 0;
  p.for_each_field([&](const FieldInfo& f, const auto& v) {
    using T = typename std::remove_reference_t<decltype(v)>::value_type;
    if (!(f.flags & field::kForce) && std::string(f.name) != "id") {
      for (std::size_t i = 0; i < p.n_local; ++i) ASSERT_EQ(v[i], value_for<T>(k, p.id[i])) << f.name;
    }
    ++k;
  });
}

TEST(ParticleFields, RecordsCarryExactlyTheFlaggedFields) {
  const ParticleData src = shuffled(50, 2);
  const std::size_t bytes = src.record_bytes<field::kGhost>();
  std::size_t expect = 0;
  for (const FieldInfo& f : ParticleData::fields())
    if (f.flags & field::kGhost) expect += f.elem_bytes;
  EXPECT_EQ(bytes, expect);
  ParticleData dst;
  dst.enable_mask(src.optional_mask());
  dst.resize(50);
  dst.n_local = 50;
  std::vector<std::byte> rec(bytes);
  for (std::size_t i = 0; i < 50; ++i) {
    src.pack<field::kGhost>(i, rec.data());
    dst.unpack<field::kGhost>(rec.data(), i);
  }
  expect_consistent(dst, 50, field::kGhost);
  ParticleData all;
  all.enable_mask(src.optional_mask());
  all.resize(50);
  for (std::size_t i = 0; i < 50; ++i) src.copy_to<field::kMigrate>(i, all, i);
  expect_consistent(all, 50, field::kMigrate);
}

TEST(ParticleFields, AnOptionalFieldCostsNothingUntilEnabledAndThenFollowsEveryPath) {
  ASSERT_NE(every_optional(), 0u) << "the list has no optional field to test";
  ParticleData p;
  p.resize(40);
  p.n_local = 40;
  // Not enabled: empty, not visited, not in records.
  std::size_t fixed_ghost = 0;
  for (const FieldInfo& f : ParticleData::fields()) {
    if (f.flags & field::kOptional) {
      EXPECT_FALSE(p.enabled(f.name)) << f.name;
    } else if (f.flags & field::kGhost) {
      fixed_ghost += f.elem_bytes;
    }
  }
  EXPECT_TRUE(p.temp.empty());
  EXPECT_EQ(p.record_bytes<field::kGhost>(), fixed_ghost);
  p.for_each_field([&](const FieldInfo& f, const auto&) { EXPECT_FALSE(f.flags & field::kOptional) << f.name; });
  p.resize(60);
  EXPECT_TRUE(p.temp.empty());
  // Enabled: sized to the stored particles, zero, and carried by the records it is flagged for.
  p.enable("temp");
  ASSERT_EQ(p.temp.size(), 60u);
  EXPECT_EQ(p.temp[59], 0.0);
  EXPECT_EQ(p.record_bytes<field::kGhost>(), fixed_ghost + sizeof(double));
  EXPECT_TRUE(p.temp_rate.empty());  // enabling one field leaves the others alone
  // A copy into a ParticleData without the field skips it rather than writing past an empty array.
  p.temp[3] = 2.5;
  ParticleData plain;
  plain.resize(60);
  p.copy_to<field::kMigrate>(3, plain, 0);
  EXPECT_TRUE(plain.temp.empty());
  EXPECT_THROW(p.enable("no_such_field"), std::invalid_argument);
}

TEST(StateCheckpoint, AnOptionalFieldTravelsOnlyWhereItIsHeld) {
  ParticleData p = shuffled(20, 5);
  const fs::path file = temp_file("optional.mdpd");
  StateHeader h;
  write_state_checkpoint(file, h, p, {});
  const StateCheckpoint with = read_state_checkpoint(file);
  // The reader holds the optional fields the writer stored (those flagged kCheckpoint), no others.
  std::uint64_t stored = 0;
  for (std::size_t k = 0; k < ParticleData::kFieldCount; ++k)
    if (ParticleData::fields()[k].flags & field::kCheckpoint) stored |= std::uint64_t{1} << k;
  ASSERT_NE(p.optional_mask() & stored, 0u);
  EXPECT_EQ(with.particles.optional_mask(), p.optional_mask() & stored);
  expect_consistent(with.particles, 20, field::kCheckpoint);
  ParticleData plain;
  plain.resize(20);
  plain.n_local = 20;
  for (std::size_t i = 0; i < 20; ++i) plain.id[i] = static_cast<std::uint32_t>(i + 1);
  write_state_checkpoint(file, h, plain, {});
  const StateCheckpoint without = read_state_checkpoint(file);
  EXPECT_EQ(without.particles.optional_mask(), 0u);
  EXPECT_TRUE(without.particles.temp.empty());
}

TEST(StateCheckpoint, RoundTripKeepsEveryCheckpointField) {
  ParticleData p = shuffled(300, 3);
  StateHeader h;
  h.step = 1234;
  h.neighbor_builds = 99;
  h.seed = 42;
  h.dt = 0.025;
  h.n_species = 2;
  h.box = {5, 6, 7};
  const std::vector<CheckpointSection> sections = {{"thermo", {std::byte{1}, std::byte{2}, std::byte{3}}},
                                                   {"walls", {}},
                                                   {"fields/slab", {std::byte{4}}}};
  const fs::path file = temp_file("roundtrip.mdpd");
  write_state_checkpoint(file, h, p, sections);
  const StateCheckpoint c = read_state_checkpoint(file);
  EXPECT_EQ(c.header.step, 1234u);
  EXPECT_EQ(c.header.neighbor_builds, 99u);
  EXPECT_EQ(c.header.seed, 42u);
  EXPECT_EQ(c.header.dt, 0.025);
  EXPECT_EQ(c.header.n_species, 2u);
  EXPECT_EQ(c.header.box[2], 7.0);
  EXPECT_EQ(c.sections, sections);
  ASSERT_EQ(c.particles.n_local, 300u);
  EXPECT_EQ(c.particles.id, std::vector<std::uint32_t>(p.id.begin(), p.id.begin() + 300));
  expect_consistent(c.particles, 300, field::kCheckpoint);
  // Without sections there are none.
  write_state_checkpoint(file, h, p, {});
  EXPECT_TRUE(read_state_checkpoint(file).sections.empty());
}

TEST(StateCheckpoint, TheObserversBlobOfFormat6SplitsIntoNamedSections) {
  // The blob Observers::save wrote up to format 6: thermo sums, then parts with a presence flag and
  // parts by name, each length-prefixed.
  using B = std::vector<std::byte>;
  const B profile{std::byte{1}}, msd{std::byte{2}, std::byte{3}}, grid{std::byte{4}}, tension{std::byte{5}},
      walls{std::byte{6}}, droplet{std::byte{7}};
  auto part = [](ByteWriter& w, const B* bytes) {
    w.put<std::uint8_t>(bytes ? 1 : 0);
    w.put_vector(bytes ? *bytes : B{});
  };
  ByteWriter w;
  w.put<double>(1.5);
  w.put<double>(2.5);
  w.put<std::uint64_t>(3);
  part(w, &profile);
  part(w, nullptr);  // no RDF
  part(w, &msd);
  const std::size_t before_fields = w.size();
  w.put<std::uint64_t>(1);
  w.put_string("slab");
  w.put_vector(grid);
  part(w, &tension);
  w.put<std::uint64_t>(1);
  w.put_string("walls");
  w.put_vector(walls);
  part(w, &droplet);
  part(w, nullptr);  // no stress profile
  const std::vector<CheckpointSection> sections = split_observer_state(w.bytes(), "blob");
  ByteWriter thermo;
  thermo.put<double>(1.5);
  thermo.put<double>(2.5);
  thermo.put<std::uint64_t>(3);
  const std::vector<CheckpointSection> expected{{"thermo", thermo.bytes()},    {"velocity_profile", profile},
                                                {"msd", msd},                 {"fields/slab", grid},
                                                {"surface_tension", tension}, {"walls", walls},
                                                {"droplet", droplet}};
  EXPECT_EQ(sections, expected);
  // A blob from before the binned fields ends after the MSD.
  const B early(w.bytes().begin(), w.bytes().begin() + static_cast<std::ptrdiff_t>(before_fields));
  EXPECT_EQ(split_observer_state(early, "blob"),
            (std::vector<CheckpointSection>(expected.begin(), expected.begin() + 3)));
  // A damaged one is refused.
  const B cut(w.bytes().begin(), w.bytes().end() - 3);
  EXPECT_THROW(split_observer_state(cut, "blob"), ConfigError);
}

TEST(StateCheckpoint, AnOlderPayloadVersionIsRefusedNamingFileAndVersions) {
  // The layout the code before the field list wrote (tag "MESODPD3", then step, builds, seed, dt,
  // species, box, and fixed arrays), inside the same container.
  ByteWriter w;
  w.put<std::uint64_t>(0x4d45534f44504433ull);
  w.put<std::uint64_t>(10);
  w.put<std::uint64_t>(10);
  w.put<std::uint64_t>(42);
  w.put<double>(0.04);
  w.put<std::uint64_t>(1);
  for (int d = 0; d < 3; ++d) w.put<double>(5.0);
  w.put_vector(std::vector<std::uint32_t>{1, 2});
  const fs::path file = temp_file("old_format.mdpd");
  write_checkpoint_file(file, w.bytes());
  try {
    read_state_checkpoint(file);
    FAIL() << "an old checkpoint was read";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(file.string()), std::string::npos) << m;
    EXPECT_NE(m.find("format 3"), std::string::npos) << m;
    EXPECT_NE(m.find("format " + std::to_string(kStateFormatVersion)), std::string::npos) << m;
  }
  // A payload that is not a state checkpoint at all.
  ByteWriter other;
  other.put<std::uint64_t>(0x1234);
  write_checkpoint_file(file, other.bytes());
  EXPECT_THROW(read_state_checkpoint(file), ConfigError);
}

TEST(IdMap, FindsEveryIdAfterReorderingAndReportsMissingOnes) {
  for (const bool sparse : {false, true}) {
    ParticleData p = shuffled(2000, 4);
    if (sparse)
      for (auto& id : p.id) id = id * 7919u + 3u;  // spread over a wide range: the hash table
    // Ghost copies of some locals, one of them twice.
    const std::size_t n = p.n_local;
    p.resize(n + 3);
    p.n_ghost = 3;
    for (std::size_t g = 0; g < 3; ++g) p.id[n + g] = p.id[g == 2 ? 0 : g];
    p.mark_reordered();
    IdMap map;
    map.refresh(p);
    EXPECT_EQ(map.hashed(), sparse);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::uint32_t at = map.find(p.id[i]);
      ASSERT_NE(at, IdMap::kNotHere);
      ASSERT_EQ(p.id[at], p.id[i]);
      ASSERT_LT(at, n) << "the owned copy comes first";
    }
    EXPECT_EQ(map.find(sparse ? 5u : 2001u), IdMap::kNotHere);
    EXPECT_EQ(map.find(0u), IdMap::kNotHere);
    // Nothing is rebuilt while the particles do not change; a permute makes the map stale.
    const auto builds = map.rebuilds();
    map.refresh(p);
    EXPECT_EQ(map.rebuilds(), builds);
    std::vector<std::uint32_t> order(n);
    std::iota(order.rbegin(), order.rend(), 0u);
    p.permute(order);
    EXPECT_FALSE(map.fresh(p));
    for (std::size_t i = 0; i < p.size(); ++i) ASSERT_EQ(map.find(p, p.id[i]), i);
    EXPECT_EQ(map.rebuilds(), builds + 1);
  }
}
