// A TOML table of the configuration with its full dotted name (toml++ stays inside src/schema/): unknown
// keys are refused on construction, typed accessors name the key in every error, and read_keys() fills a
// struct from the keys a model declared (include/mesodpd/key_table.hpp).
#pragma once
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mesodpd/key_table.hpp"

namespace mesodpd::schema {

// ---------------------------------------------------------------------------------------------
// Message helpers

// Case-insensitive Levenshtein distance, used to guess what a misspelt key or choice meant.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The candidate nearest to `given`, if near enough to be a plausible typo.
inline std::optional<std::string_view> closest(std::string_view given,
                                        const std::vector<std::string_view>& candidates) {
  std::optional<std::string_view> best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string_view c : candidates) {
    const std::size_t d = edit_distance(given, c);
    if (d < best_distance) best = c, best_distance = d;
  }
  if (best_distance > std::max<std::size_t>(2, given.size() / 3)) return std::nullopt;
  return best;
}

inline std::string join(const std::vector<std::string_view>& items, std::string_view quote = "") {
  std::string out;
  for (const std::string_view item : items) {
    if (!out.empty()) out += ", ";
    out += fmt::format("{}{}{}", quote, item, quote);
  }
  return out;
}

inline std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time:
      return "a date/time";
    default:
      return "an empty value";
  }
}

// The value as the user wrote it (near enough), for "key = value: problem" messages.
inline std::string show(const toml::node& n) {
  if (const auto* v = n.as_integer()) return fmt::format("{}", v->get());
  if (const auto* v = n.as_floating_point()) return fmt::format("{}", v->get());
  if (const auto* v = n.as_string()) return fmt::format("\"{}\"", v->get());
  if (const auto* v = n.as_boolean()) return v->get() ? "true" : "false";
  if (const auto* arr = n.as_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < arr->size(); ++i) out += (i ? ", " : "") + show(*arr->get(i));
    return out + "]";
  }
  if (n.is_table()) return "{...}";
  return "<" + type_name(n) + ">";
}

// ---------------------------------------------------------------------------------------------
// Section: one TOML table plus its full dotted name. Unknown keys are rejected on construction,
// so a typo is reported before any value check; accessors return nullopt for absent keys.
class Section {
 public:
  Section(const toml::table& table, std::string path, std::vector<std::string_view> allowed,
          const std::string& source)
      : table_(&table), path_(std::move(path)), allowed_(std::move(allowed)), source_(&source) {
    for (const auto& [key, value] : table) {
      const std::string_view k = key.str();
      if (std::find(allowed_.begin(), allowed_.end(), k) != allowed_.end()) continue;
      std::string hint;
      if (const auto best = closest(k, allowed_)) {
        hint = fmt::format(" (did you mean '{}'?)", name(*best));
      } else {
        hint = fmt::format("; valid keys {}: {}", path_.empty() ? "at top level" : "in [" + path_ + "]",
                           join(allowed_));
      }
      throw ConfigError(fmt::format("{}unknown key '{}'{}", at(key.source()), name(k), hint), name(k));
    }
  }

  std::string name(std::string_view key) const {
    return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
  }
  const std::string& path() const { return path_; }

  const toml::node* get(std::string_view key) const {
    if (std::find(allowed_.begin(), allowed_.end(), key) == allowed_.end()) {
      throw std::logic_error(fmt::format("config reader asked for undeclared key '{}'", name(key)));
    }
    return table_->get(key);
  }
  bool has(std::string_view key) const { return get(key) != nullptr; }

  // "file:line:col: " where the region is known, "file: " otherwise.
  std::string at(const toml::source_region& r) const {
    if (r.begin.line == 0) return *source_ + ": ";
    return fmt::format("{}:{}:{}: ", *source_, r.begin.line, r.begin.column);
  }

  // `key` may carry an index suffix ("box[1]") when `n` is an array element.
  [[noreturn]] void bad(std::string_view key, const toml::node& n, std::string_view why) const {
    throw ConfigError(fmt::format("{}{} = {}: {}", at(n.source()), name(key), show(n), why), name(key));
  }
  [[noreturn]] void bad(std::string_view key, std::string_view why) const { bad(key, *get(key), why); }
  [[noreturn]] void wrong_type(std::string_view key, const toml::node& n, std::string_view expected) const {
    bad(key, n, fmt::format("expected {}, got {}", expected, type_name(n)));
  }
  [[noreturn]] void missing(std::string_view key, std::string_view why = {}) const {
    throw ConfigError(fmt::format("{}missing required key '{}'{}", at(table_->source()), name(key), why), name(key));
  }

  std::optional<double> real(std::string_view key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    if (const auto* f = n->as_floating_point()) return f->get();
    if (const auto* i = n->as_integer()) return static_cast<double>(i->get());
    wrong_type(key, *n, "a number");
  }

  std::optional<std::int64_t> integer(std::string_view key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    if (const auto* i = n->as_integer()) return i->get();
    wrong_type(key, *n, "an integer");
  }

  std::optional<bool> boolean(std::string_view key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    if (const auto* b = n->as_boolean()) return b->get();
    wrong_type(key, *n, "a boolean (true or false)");
  }

  std::optional<std::string> string(std::string_view key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    if (const auto* s = n->as_string()) return s->get();
    wrong_type(key, *n, "a string");
  }

  // Exactly three numbers (their ranges are validate()'s).
  std::optional<std::array<double, 3>> vec3(std::string_view key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    const toml::array* arr = n->as_array();
    if (!arr) wrong_type(key, *n, "an array of 3 numbers");
    if (arr->size() != 3) bad(key, *n, fmt::format("expected 3 numbers, got {}", arr->size()));
    std::array<double, 3> out{};
    for (std::size_t d = 0; d < 3; ++d) {
      const toml::node& e = *arr->get(d);
      if (const auto* f = e.as_floating_point()) {
        out[d] = f->get();
      } else if (const auto* i = e.as_integer()) {
        out[d] = static_cast<double>(i->get());
      } else {
        wrong_type(fmt::format("{}[{}]", key, d), e, "a number");
      }
    }
    return out;
  }

  // Exactly three booleans (one per axis).
  std::optional<std::array<bool, 3>> bool3(std::string_view key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    const toml::array* arr = n->as_array();
    if (!arr) wrong_type(key, *n, "an array of 3 booleans");
    if (arr->size() != 3) bad(key, *n, fmt::format("expected 3 booleans, got {}", arr->size()));
    std::array<bool, 3> out{};
    for (std::size_t d = 0; d < 3; ++d) {
      const toml::node& e = *arr->get(d);
      const auto* b = e.as_boolean();
      if (!b) wrong_type(fmt::format("{}[{}]", key, d), e, "a boolean (true or false)");
      out[d] = b->get();
    }
    return out;
  }

  std::optional<std::vector<std::string>> strings(std::string_view key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    const toml::array* arr = n->as_array();
    if (!arr) wrong_type(key, *n, "an array of strings");
    std::vector<std::string> out;
    for (std::size_t k = 0; k < arr->size(); ++k) {
      const toml::node& e = *arr->get(k);
      const auto* s = e.as_string();
      if (!s) wrong_type(fmt::format("{}[{}]", key, k), e, "a string");
      out.push_back(s->get());
    }
    return out;
  }

  // A string that must be one of `options`, mapped to its enum value.
  template <class E>
  std::optional<E> choice(std::string_view key,
                          std::initializer_list<std::pair<std::string_view, E>> options) const {
    std::vector<std::pair<std::string, int>> numbered;
    for (const auto& [word, value] : options) numbered.emplace_back(std::string(word), static_cast<int>(value));
    const std::optional<int> v = choice_of(key, numbered);
    if (!v) return std::nullopt;
    return static_cast<E>(*v);
  }

  // A string that must be one of the declared `options` (word, integer value).
  std::optional<int> choice_of(std::string_view key, const std::vector<std::pair<std::string, int>>& options) const {
    const std::optional<std::string> s = string(key);
    if (!s) return std::nullopt;
    std::vector<std::string_view> words;
    for (const auto& [word, value] : options) {
      if (word == *s) return value;
      words.push_back(word);
    }
    std::string why = fmt::format("must be one of {}", join(words, "\""));
    if (const auto best = closest(*s, words)) why += fmt::format(" (did you mean \"{}\"?)", *best);
    bad(key, why);
  }

  // The sub-table `key`, or nothing when absent.
  std::optional<Section> table(std::string_view key, std::vector<std::string_view> allowed) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    const toml::table* t = n->as_table();
    if (!t) wrong_type(key, *n, fmt::format("a table ([{}])", name(key)));
    return Section(*t, name(key), std::move(allowed), *source_);
  }

  // The sub-table `key`, or an empty one (all defaults) when absent.
  Section table_or_empty(std::string_view key, std::vector<std::string_view> allowed) const {
    static const toml::table kEmpty;
    if (auto t = table(key, allowed)) return *std::move(t);
    return Section(kEmpty, name(key), std::move(allowed), *source_);
  }

  // The array of tables `key` ([[key]] blocks), empty when absent.
  std::vector<Section> tables(std::string_view key, const std::vector<std::string_view>& allowed) const {
    std::vector<Section> out;
    const toml::node* n = get(key);
    if (!n) return out;
    const toml::array* arr = n->as_array();
    if (!arr || !arr->is_array_of_tables()) {
      wrong_type(key, *n, fmt::format("an array of tables ([[{}]] blocks)", name(key)));
    }
    for (std::size_t k = 0; k < arr->size(); ++k) {
      out.emplace_back(*arr->get(k)->as_table(), fmt::format("{}[{}]", name(key), k), allowed, *source_);
    }
    return out;
  }

 private:
  const toml::table* table_;
  std::string path_;
  std::vector<std::string_view> allowed_;
  const std::string* source_;
};

// Typed reads. Only what the spec's types cannot hold is refused here (a negative count, an int
// overflow); every range is validate()'s.

inline std::optional<std::int64_t> optional_int(const Section& s, std::string_view key, std::int64_t lo,
                                         std::int64_t hi = std::numeric_limits<std::int64_t>::max()) {
  const std::optional<std::int64_t> v = s.integer(key);
  if (v && *v < lo) s.bad(key, fmt::format("must be an integer >= {}", lo));
  if (v && *v > hi) s.bad(key, fmt::format("must be an integer <= {}", hi));
  return v;
}

inline void read_uint(const Section& s, std::string_view key, std::uint64_t& out) {
  if (const auto v = optional_int(s, key, 0)) out = static_cast<std::uint64_t>(*v);
}

inline void read_int(const Section& s, std::string_view key, int& out) {
  if (const auto v = optional_int(s, key, INT_MIN, INT_MAX)) out = static_cast<int>(*v);
}

inline void read_real(const Section& s, std::string_view key, double& out) {
  if (const auto v = s.real(key)) out = *v;
}


// Reads every declared key of `table` that `s` holds into `out` (types checked here; ranges are
// validate()'s, through KeyTable::check). Custom keys are left to their model's code.
// A Section seen through the declared keys' reader interface (include/mesodpd/key_table.hpp).
class SectionReader final : public keys::Reader {
 public:
  explicit SectionReader(const Section& s) : s_(s) {}
  bool has(std::string_view key) const override { return s_.has(key); }
  void read(std::string_view key, double& out) const override { read_real(s_, key, out); }
  void read(std::string_view key, std::optional<double>& out) const override {
    if (const auto v = s_.real(key)) out = *v;
  }
  void read(std::string_view key, int& out) const override { read_int(s_, key, out); }
  void read(std::string_view key, std::uint64_t& out) const override { read_uint(s_, key, out); }
  void read(std::string_view key, bool& out) const override {
    if (const auto v = s_.boolean(key)) out = *v;
  }
  void read(std::string_view key, std::string& out) const override {
    if (auto v = s_.string(key)) out = std::move(*v);
  }
  void read(std::string_view key, std::array<double, 3>& out) const override {
    if (const auto v = s_.vec3(key)) out = *v;
  }
  void read(std::string_view key, std::optional<std::array<double, 3>>& out) const override {
    if (const auto v = s_.vec3(key)) out = *v;
  }
  void read(std::string_view key, std::array<int, 3>& out, std::string_view noun) const override {
    if (const auto v = s_.vec3(key)) {
      for (std::size_t d = 0; d < 3; ++d) {
        const double x = (*v)[d];
        if (!(std::abs(x) <= INT_MAX) || x != std::trunc(x))
          s_.bad(key, fmt::format("element {} is {}, not a whole number of {}", d, x, noun));
        out[d] = static_cast<int>(x);
      }
    }
  }
  void read(std::string_view key, std::array<bool, 3>& out) const override {
    if (const auto v = s_.bool3(key)) out = *v;
  }
  void read(std::string_view key, std::vector<std::string>& out) const override {
    if (auto v = s_.strings(key)) out = std::move(*v);
  }
  std::optional<int> choice(std::string_view key,
                            const std::vector<std::pair<std::string, int>>& options) const override {
    return s_.choice_of(key, options);
  }
  [[noreturn]] void missing(std::string_view key, std::string_view hint) const override { s_.missing(key, hint); }
  [[noreturn]] void refuse(std::string_view key, std::string_view why) const override { s_.bad(key, why); }
  std::string full_name(std::string_view key) const override { return s_.name(key); }
  std::string written(std::string_view key) const override { return show(*s_.get(key)); }

 private:
  const Section& s_;
};

template <class T>
void read_keys(const keys::KeyTable<T>& table, const Section& s, T& out) {
  keys::read_keys(table, SectionReader(s), out);
}

}  // namespace mesodpd::schema
