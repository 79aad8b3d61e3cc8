// Reading a TOML configuration file (schema: docs/config.md) into a validated SimulationSpec, for
// programs that start from a file and then adjust the spec in code (docs/api.md).
#pragma once
#include <filesystem>
#include <string>
#include <string_view>

#include "mesodpd/spec.hpp"

namespace mesodpd {

// Parses `file`, checks key names and types, and runs validate(). Relative paths inside it
// (init.lammps_data) are resolved against the file's directory. Throws ConfigError naming the file,
// and the key with its line and column where the problem is in a key.
SimulationSpec load_config(const std::filesystem::path& file);

// Same, for TOML text already in memory. `source_name` is used in messages and, when it names a
// file, its directory anchors relative paths (the current directory otherwise).
SimulationSpec parse_config(std::string_view toml_text, const std::string& source_name);

}  // namespace mesodpd
