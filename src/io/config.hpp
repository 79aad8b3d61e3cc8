// Reads a TOML configuration file into a validated SimulationSpec (schema: docs/config.md).
#pragma once
#include <filesystem>
#include <string>
#include <string_view>

#include "mesodpd/spec.hpp"

namespace mesodpd {

// Parses and validates `file`. Relative paths inside it (init.lammps_data) are resolved against the
// file's directory. Throws ConfigError naming the file, and the key where the problem is in a key.
SimulationSpec load_config(const std::filesystem::path& file);

// Same, for TOML text already in memory. `source_name` is used in messages and, when it names a
// file, its directory anchors relative paths (the current directory otherwise).
SimulationSpec parse_config(std::string_view toml_text, const std::string& source_name);

}  // namespace mesodpd
