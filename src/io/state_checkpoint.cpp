// Encoding and decoding of the state checkpoint's payload from the particle field list.
#include "io/state_checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "io/byte_buffer.hpp"
#include "io/checkpoint_file.hpp"

namespace mesodpd {

namespace {

// "MESODPD" in the high seven bytes and the version as an ASCII digit in the lowest: version 3 is the
// tag the code before the field list wrote.
constexpr std::uint64_t kTagStem = 0x4d45534f44504400ull;
constexpr std::uint64_t tag_of(int version) { return kTagStem | static_cast<std::uint64_t>('0' + version); }

}  // namespace

void write_state_checkpoint(const std::filesystem::path& file, const StateHeader& h, const ParticleData& all,
                            const std::vector<CheckpointSection>& sections, const Topology* topology) {
  ByteWriter w;
  w.put<std::uint64_t>(tag_of(kStateFormatVersion));
  w.put<std::uint64_t>(h.step);
  w.put<std::uint64_t>(h.neighbor_builds);
  w.put<std::uint64_t>(h.seed);
  w.put<double>(h.dt);
  w.put<std::uint64_t>(h.n_species);
  for (double l : h.box) w.put<double>(l);
  const std::size_t n = all.n_local;
  w.put<std::uint64_t>(n);
  // The checkpointed fields this run holds (an optional field only where its model enabled it).
  std::uint64_t n_fields = 0;
  all.for_each_field([&](const FieldInfo& f, const auto&) { n_fields += (f.flags & field::kCheckpoint) ? 1 : 0; });
  w.put<std::uint64_t>(n_fields);
  all.for_each_field([&](const FieldInfo& f, const auto& v) {
    if (!(f.flags & field::kCheckpoint)) return;
    w.put_string(f.name);
    w.put<char>(f.kind);
    w.put<std::uint8_t>(static_cast<std::uint8_t>(f.elem_bytes));
    w.put_vector(std::span(v.data(), n));
  });
  w.put<std::uint64_t>(sections.size());
  for (const CheckpointSection& section : sections) {
    w.put_string(section.name);
    w.put_vector(section.bytes);
  }
  // Topology: bonds as (a, b, type) and angles as (a, b, c, type), 32-bit words.
  std::vector<std::uint32_t> words;
  if (topology)
    for (const Bond& b : topology->bonds) words.insert(words.end(), {b.a, b.b, static_cast<std::uint32_t>(b.type)});
  w.put_vector(words);
  words.clear();
  if (topology)
    for (const Angle& a : topology->angles)
      words.insert(words.end(), {a.a, a.b, a.c, static_cast<std::uint32_t>(a.type)});
  w.put_vector(words);
  // The configuration that the particles belong to, if the writer gave it.
  w.put<std::uint8_t>(h.has_config ? 1 : 0);
  if (h.has_config) {
    for (const bool p : h.periodic) w.put<std::uint8_t>(p ? 1 : 0);
    w.put<std::uint64_t>(h.species.size());
    for (const CheckpointSpecies& sp : h.species) {
      w.put_string(sp.name);
      w.put<double>(sp.mass);
      w.put<std::uint64_t>(sp.count);
      w.put<std::uint8_t>(sp.frozen ? 1 : 0);
    }
  }
  // Dihedrals as (a, b, c, d, type), 32-bit words (format 8).
  words.clear();
  if (topology)
    for (const Dihedral& d : topology->dihedrals)
      words.insert(words.end(), {d.a, d.b, d.c, d.d, static_cast<std::uint32_t>(d.type)});
  w.put_vector(words);
  write_checkpoint_file(file, w.bytes());
}

StateCheckpoint read_state_checkpoint(const std::filesystem::path& file) {
  const std::vector<std::byte> bytes = read_checkpoint_file(file);
  const std::string where = "checkpoint '" + file.string() + "'";
  ByteReader r(bytes, where);
  const auto tag = r.get<std::uint64_t>();
  if ((tag & ~std::uint64_t{0xff}) != kTagStem)
    throw ConfigError(fmt::format("{}: not a mesodpd state checkpoint", where));
  const int version = static_cast<int>(tag & 0xff) - '0';
  if (version < kOldestReadableStateFormat || version > kStateFormatVersion)
    throw ConfigError(fmt::format(
        "{}: state format {} cannot be read by this mesodpd, which reads format {} (and format {} up to {}); continue "
        "that run with the mesodpd that wrote it, or start it again",
        where, version, kStateFormatVersion, kOldestReadableStateFormat, kStateFormatVersion - 1));
  StateCheckpoint c;
  StateHeader& h = c.header;
  h.step = r.get<std::uint64_t>();
  h.neighbor_builds = r.get<std::uint64_t>();
  h.seed = r.get<std::uint64_t>();
  h.dt = r.get<double>();
  h.n_species = r.get<std::uint64_t>();
  for (double& l : h.box) l = r.get<double>();
  const auto n = r.get<std::uint64_t>();
  const auto n_fields = r.get<std::uint64_t>();
  ParticleData& p = c.particles;
  p.resize(static_cast<std::size_t>(n));
  p.n_local = static_cast<std::size_t>(n);
  std::vector<bool> seen(ParticleData::fields().size(), false);
  for (std::uint64_t k = 0; k < n_fields; ++k) {
    const std::string name = r.get_string();
    const char kind = r.get<char>();
    const auto elem_bytes = r.get<std::uint8_t>();
    // An optional field in the file was held by the run that wrote it: hold it here too.
    const std::size_t at = ParticleData::field_index(name);
    if (at < ParticleData::kFieldCount && (ParticleData::fields()[at].flags & field::kOptional)) p.enable(name);
    bool found = false;
    p.for_each_field([&](const FieldInfo& f, auto& v) {
      if (found || name != f.name || !(f.flags & field::kCheckpoint)) return;
      found = true;
      using T = typename std::remove_reference_t<decltype(v)>::value_type;
      if (kind != f.kind || elem_bytes != f.elem_bytes)
        throw ConfigError(fmt::format("{}: field '{}' is stored as {}{} but this mesodpd holds it as {}{}", where, name,
                                      kind, 8 * elem_bytes, f.kind, 8 * f.elem_bytes));
      if (seen[at]) throw ConfigError(fmt::format("{}: field '{}' is stored twice", where, name));
      seen[at] = true;
      std::vector<T> values = r.get_vector<T>();
      if (values.size() != n)
        throw ConfigError(fmt::format("{}: field '{}' has {} values for {} particles", where, name, values.size(), n));
      std::copy(values.begin(), values.end(), v.begin());
    });
    if (!found) throw ConfigError(fmt::format("{}: unknown particle field '{}'", where, name));
  }
  for (std::size_t k = 0; k < seen.size(); ++k)
    if ((ParticleData::fields()[k].flags & field::kCheckpoint) && !(ParticleData::fields()[k].flags & field::kOptional) &&
        !seen[k])
      throw ConfigError(fmt::format("{}: particle field '{}' is missing", where, ParticleData::fields()[k].name));
  if (version >= 7) {
    const auto n_sections = r.get<std::uint64_t>();
    for (std::uint64_t k = 0; k < n_sections; ++k) {
      CheckpointSection section;
      section.name = r.get_string();
      section.bytes = r.get_vector<std::byte>();
      c.sections.push_back(std::move(section));
    }
  } else if (r.get<std::uint8_t>() != 0) {
    c.sections = split_observer_state(r.get_vector<std::byte>(), where);
  }
  const std::vector<std::uint32_t> bonds = r.get_vector<std::uint32_t>();
  const std::vector<std::uint32_t> angles = r.get_vector<std::uint32_t>();
  if (bonds.size() % 3 != 0 || angles.size() % 4 != 0)
    throw ConfigError(fmt::format("{}: damaged topology section", where));
  for (std::size_t k = 0; k < bonds.size(); k += 3)
    c.topology.bonds.push_back({bonds[k], bonds[k + 1], static_cast<std::int32_t>(bonds[k + 2])});
  for (std::size_t k = 0; k < angles.size(); k += 4)
    c.topology.angles.push_back({angles[k], angles[k + 1], angles[k + 2], static_cast<std::int32_t>(angles[k + 3])});
  if (version >= 6 && r.get<std::uint8_t>() != 0) {
    h.has_config = true;
    for (bool& p : h.periodic) p = r.get<std::uint8_t>() != 0;
    const auto n_species = r.get<std::uint64_t>();
    if (n_species != h.n_species) throw ConfigError(fmt::format("{}: damaged species section", where));
    for (std::uint64_t k = 0; k < n_species; ++k) {
      CheckpointSpecies sp;
      sp.name = r.get_string();
      sp.mass = r.get<double>();
      sp.count = r.get<std::uint64_t>();
      sp.frozen = r.get<std::uint8_t>() != 0;
      h.species.push_back(std::move(sp));
    }
  }
  if (version >= 8) {
    const std::vector<std::uint32_t> dihedrals = r.get_vector<std::uint32_t>();
    if (dihedrals.size() % 5 != 0) throw ConfigError(fmt::format("{}: damaged topology section", where));
    for (std::size_t k = 0; k < dihedrals.size(); k += 5)
      c.topology.dihedrals.push_back({dihedrals[k], dihedrals[k + 1], dihedrals[k + 2], dihedrals[k + 3],
                                      static_cast<std::int32_t>(dihedrals[k + 4])});
  }
  r.expect_end();
  return c;
}

std::vector<CheckpointSection> split_observer_state(const std::vector<std::byte>& blob, const std::string& context) {
  // The layout Observers::save wrote up to format 6, read as Observers::load read it.
  ByteReader r(blob, context);
  std::vector<CheckpointSection> out;
  ByteWriter thermo;
  thermo.put<double>(r.get<double>());         // temperature sum
  thermo.put<double>(r.get<double>());         // pressure sum
  thermo.put<std::uint64_t>(r.get<std::uint64_t>());  // thermo rows
  out.push_back({section_name::kThermo, thermo.take()});
  // A part with its presence flag: absent parts have no section.
  auto part = [&](const char* name) {
    const bool present = r.get<std::uint8_t>() != 0;
    std::vector<std::byte> bytes = r.get_vector<std::byte>();
    if (present) out.push_back({name, std::move(bytes)});
  };
  // Parts by name (binned-fields grids, other models' sections).
  auto named = [&](const std::string& prefix) {
    const auto count = r.get<std::uint64_t>();
    for (std::uint64_t k = 0; k < count; ++k) {
      std::string name = prefix + r.get_string();
      out.push_back({std::move(name), r.get_vector<std::byte>()});
    }
  };
  part(section_name::kVelocityProfile);
  part(section_name::kRdf);
  part(section_name::kMsd);
  // Each later part was added by a later version: a blob from before it ends here.
  if (r.remaining() == 0) return out;
  named(section_name::kFieldsPrefix);
  if (r.remaining() == 0) return out;
  part(section_name::kSurfaceTension);
  if (r.remaining() == 0) return out;
  named("");
  if (r.remaining() == 0) return out;
  part(section_name::kDroplet);
  if (r.remaining() == 0) return out;
  part(section_name::kStressProfile);
  r.expect_end();
  return out;
}

}  // namespace mesodpd
