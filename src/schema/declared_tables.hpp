// Every declared key table of the schema, in the order of docs/config.md: the source of the key tables
// of that page (`mesodpd keys`, tools/update_config_docs.py) and of the test that keeps them equal.
#pragma once
#include <string>
#include <vector>

#include "mesodpd/key_table.hpp"

namespace mesodpd {

struct DeclaredTable {
  std::string path;                // "integrator", "analysis.rdf"
  std::vector<keys::KeyDoc> rows;  // in declaration order
  bool repeated = false;           // written as [[path]] blocks (keys then named "path[k].key")
  std::string minimal;             // TOML lines that a block needs besides the key under test (for tests)
};

std::vector<DeclaredTable> declared_tables();

// All tables as docs/config.md holds them: each a line "<!-- keys: PATH -->" and its markdown table.
std::string declared_tables_markdown();

}  // namespace mesodpd
