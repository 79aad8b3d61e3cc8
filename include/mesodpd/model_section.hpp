// A model's own config section: the keys a module declares for a model the engine's shared schema does
// not know (a thermostat, an analysis, a field). The schema reads every listed model's section with the
// same reader, range checks and docs as its own tables (engine/installer.hpp lists the models), and
// keeps the values in SimulationSpec::models under the section's path, where the model's installer
// finds them. A section that the file does not write leaves its model off.
#pragma once
#include <any>
#include <functional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

struct ModelSection {
  std::string path;                     // "thermostat", "analysis.speed_histogram": [path] in the file
  std::vector<std::string> names;       // the keys it accepts
  std::vector<keys::KeyDoc> docs;       // its rows of docs/config.md
  std::string minimal;                  // TOML lines a table needs besides one key (docs tests)
  std::function<std::any(const keys::Reader&)> read;           // the values the table holds (defaults else)
  std::function<void(std::any&, const SimulationSpec&)> check;  // ranges, then the model's cross-checks
  std::function<std::vector<std::string>(const std::any&)> values;  // "key = value" of what differs from the defaults
  // Set for a repeatable section ([[path]] blocks, model_list_section): makes the value the model finds
  // from the blocks' values, each made by `read`. Empty: one [path] table.
  std::function<std::any(std::vector<std::any>)> gather;
};

// The section of a model whose values are a T declared by `table`; `cross_check` (optional) throws a
// SpecError naming the key for what the ranges cannot say. The section keeps a reference to `table`,
// so it must live as long as the program: a function-local static, as every *_keys() function has.
template <class T>
ModelSection model_section(const keys::KeyTable<T>& table,
                           std::type_identity_t<std::function<void(const T&, const SimulationSpec&)>> cross_check = {},
                           std::string minimal = {}) {
  ModelSection s;
  s.path = table.path();
  for (std::string_view n : table.names()) s.names.emplace_back(n);
  s.docs = table.docs();
  s.minimal = std::move(minimal);
  s.read = [&table](const keys::Reader& r) {
    T value{};
    keys::read_keys(table, r, value);
    return std::any(std::move(value));
  };
  s.check = [&table, cross_check](std::any& value, const SimulationSpec& spec) {
    const T& v = std::any_cast<const T&>(value);
    table.check(table.path(), v);
    if (cross_check) cross_check(v, spec);
  };
  s.values = [&table](const std::any& value) { return table.set_values(std::any_cast<const T&>(value)); };
  return s;
}

// A repeatable section: [[path]] blocks, each declared by `table`; the model finds a std::vector<T> in
// file order (SimulationSpec::model<std::vector<T>>(path)). Each block is range-checked under its own
// name ("source[1].rate"), then `cross_check` sees the whole list.
template <class T>
ModelSection model_list_section(
    const keys::KeyTable<T>& table,
    std::type_identity_t<std::function<void(const std::vector<T>&, const SimulationSpec&)>> cross_check = {},
    std::string minimal = {}) {
  ModelSection s = model_section<T>(table, {}, std::move(minimal));
  s.gather = [](std::vector<std::any> items) {
    std::vector<T> list;
    for (std::any& a : items) list.push_back(std::any_cast<T&&>(std::move(a)));
    return std::any(std::move(list));
  };
  s.check = [&table, cross_check](std::any& value, const SimulationSpec& spec) {
    const std::vector<T>& list = std::any_cast<const std::vector<T>&>(value);
    for (std::size_t k = 0; k < list.size(); ++k) table.check(table.path() + "[" + std::to_string(k) + "]", list[k]);
    if (cross_check) cross_check(list, spec);
  };
  s.values = [&table](const std::any& value) {
    std::vector<std::string> out;
    const std::vector<T>& list = std::any_cast<const std::vector<T>&>(value);
    for (std::size_t k = 0; k < list.size(); ++k)
      for (std::string& v : table.set_values(list[k])) out.push_back("[" + std::to_string(k) + "] " + std::move(v));
    return out;
  };
  return s;
}

}  // namespace mesodpd
