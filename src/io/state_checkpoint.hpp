// The state checkpoint's payload: run header, the particle fields the field list marks kCheckpoint
// (stored by name and element type), and the named sections of the models (each analysis's running
// averages, the walls' drag and adaptive force, ...), opaque here.
// The payload goes inside the checksummed container of io/checkpoint_file.hpp.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/particle_data.hpp"
#include "core/topology.hpp"

namespace mesodpd {

// Version of the payload layout, stored as the tag "MESODPD<version>". 3: fixed list of arrays (up
// to this refactor); 4: named, typed fields from the particle field list; 5: the molecular topology
// (bonds and angles by global id) after the observers' section; 6: the run's configuration that the
// checkpoint fixes (periodicity, species) at the end; 7: named sections, one per model, in place of the
// observers' one blob; 8: the dihedrals (a, b, c, d, type) at the end. Formats 5 to 7 are still read
// (without dihedrals): their blob is split into the sections of format 7 (split_observer_state below),
// and a format 5 file has no configuration.
inline constexpr int kStateFormatVersion = 8;
inline constexpr int kOldestReadableStateFormat = 5;

// A species as the run that wrote the checkpoint configured it ([[species]] name, mass, count, frozen).
struct CheckpointSpecies {
  std::string name;
  double mass = 0;
  std::uint64_t count = 0;
  bool frozen = false;
};

struct StateHeader {
  std::uint64_t step = 0;
  std::uint64_t neighbor_builds = 0;  // so thermo.csv's neighbor_builds column continues across a restart
  std::uint64_t seed = 0;
  double dt = 0;
  std::uint64_t n_species = 0;
  std::array<double, 3> box{};
  // The configuration the particles belong to (format 6 on; has_config is false for a format 5 file).
  bool has_config = false;
  std::array<bool, 3> periodic{true, true, true};
  std::vector<CheckpointSpecies> species;
};

// A model's part of the checkpoint, by name: a restart hands the bytes to the model that registers a
// section of that name, so a model switched off at the restart skips its section and one switched on
// starts afresh.
struct CheckpointSection {
  std::string name;
  std::vector<std::byte> bytes;
  bool operator==(const CheckpointSection&) const = default;
};

// The names the analyses save their sections under (engine/install_analyses.cpp); a format 5 or 6
// observers' blob is split into these. A binned-fields grid's is kFieldsPrefix + its name.
namespace section_name {
inline constexpr const char* kThermo = "thermo";
inline constexpr const char* kVelocityProfile = "velocity_profile";
inline constexpr const char* kRdf = "rdf";
inline constexpr const char* kMsd = "msd";
inline constexpr const char* kFieldsPrefix = "fields/";
inline constexpr const char* kSurfaceTension = "surface_tension";
inline constexpr const char* kDroplet = "droplet";
inline constexpr const char* kStressProfile = "stress_profile";
}  // namespace section_name

// What a checkpoint holds: the header, every particle (locals only, n_local of them, in the file's
// order), the models' sections and the topology.
struct StateCheckpoint {
  StateHeader header;
  ParticleData particles;
  std::vector<CheckpointSection> sections;
  Topology topology;
};

// Writes the first all.n_local particles of `all` (every field flagged kCheckpoint) and the sections
// atomically. Throws ConfigError naming the file.
void write_state_checkpoint(const std::filesystem::path& file, const StateHeader& header, const ParticleData& all,
                            const std::vector<CheckpointSection>& sections, const Topology* topology = nullptr);

// The observers' one blob of formats 5 and 6 as the sections of format 7: the thermo sums, then
// length-prefixed parts (each with a presence flag) for the profile, RDF and MSD, the binned-fields
// grids by name, the surface tension, the other models' sections by name, the droplet and the stress
// profile (a blob written before a part existed ends before it). Throws ConfigError naming `context`.
std::vector<CheckpointSection> split_observer_state(const std::vector<std::byte>& blob, const std::string& context);

// Reads a checkpoint written by write_state_checkpoint (or by format 5 or 6). Throws ConfigError naming the file for a
// damaged file (container checks), another payload version (naming both versions), a field missing,
// unknown or of another element type, or arrays of different lengths. Fields not flagged kCheckpoint
// come back zero.
StateCheckpoint read_state_checkpoint(const std::filesystem::path& file);

}  // namespace mesodpd
