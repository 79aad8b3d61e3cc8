// Every declared key table of the schema, in the order of docs/config.md: the source of the key tables
// of that page (`mesodpd keys`, tools/update_config_docs.py) and of the test that keeps them equal.
#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

struct DeclaredTable {
  std::string path;                // "integrator", "analysis.rdf"
  std::vector<keys::KeyDoc> rows;  // in declaration order
  bool repeated = false;           // written as [[path]] blocks (keys then named "path[k].key")
  std::string minimal;             // TOML lines that a block needs besides the key under test (for tests)
  // The values a spec holds for this table, for `mesodpd check`: for each instance of the table that
  // the spec has ("species[1]", "analysis.rdf"), its values that differ from the declared defaults as
  // "key = value unit". Empty for a table without declared values (pair).
  using Values = std::vector<std::pair<std::string, std::vector<std::string>>>;
  std::function<Values(const SimulationSpec&)> values;
};

std::vector<DeclaredTable> declared_tables();

// All tables as docs/config.md holds them: each a line "<!-- keys: PATH -->" and its markdown table.
std::string declared_tables_markdown();

// `mesodpd check`'s summary of the settings: a line per table instance that the spec sets ("  system:
// box = [20, 20, 20] r_c, kT = 1.5"), in the order of declared_tables(); a table whose presence turns
// its model on is listed even with default values. Empty when everything is at its default.
std::string declared_values_summary(const SimulationSpec& spec);
// The models' own estimates for `mesodpd check` (Model::numbers), in the list's order.
std::string model_numbers_summary(const SimulationSpec& spec);

}  // namespace mesodpd
