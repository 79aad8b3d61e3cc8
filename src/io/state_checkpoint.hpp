// The state checkpoint's payload: run header, the particle fields the field list marks kCheckpoint
// (stored by name and element type), and the observers' running averages as an opaque section.
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
// checkpoint fixes (periodicity, species) at the end. Format 5 is still read (without that part).
inline constexpr int kStateFormatVersion = 6;
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

// What a checkpoint holds: the header, every particle (locals only, n_local of them, in the file's
// order) and the observers' state if the run that wrote it had observers.
struct StateCheckpoint {
  StateHeader header;
  ParticleData particles;
  std::optional<std::vector<std::byte>> observer_state;
  Topology topology;
};

// Writes the first all.n_local particles of `all` (every field flagged kCheckpoint) atomically.
// Throws ConfigError naming the file.
void write_state_checkpoint(const std::filesystem::path& file, const StateHeader& header, const ParticleData& all,
                            const std::vector<std::byte>* observer_state, const Topology* topology = nullptr);

// Reads a checkpoint written by write_state_checkpoint. Throws ConfigError naming the file for a
// damaged file (container checks), another payload version (naming both versions), a field missing,
// unknown or of another element type, or arrays of different lengths. Fields not flagged kCheckpoint
// come back zero.
StateCheckpoint read_state_checkpoint(const std::filesystem::path& file);

}  // namespace mesodpd
