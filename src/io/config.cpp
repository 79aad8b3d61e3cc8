// TOML configuration -> SimulationSpec: every key is type-checked, range-checked and named in errors.
#include "io/config.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace mesodpd {
namespace {

namespace fs = std::filesystem;
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// Message helpers

// Case-insensitive Levenshtein distance, used to guess what a misspelt key or choice meant.
std::size_t edit_distance(std::string_view a, std::string_view b) {
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
std::optional<std::string_view> closest(std::string_view given,
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

std::string join(const std::vector<std::string_view>& items, std::string_view quote = "") {
  std::string out;
  for (const std::string_view item : items) {
    if (!out.empty()) out += ", ";
    out += fmt::format("{}{}{}", quote, item, quote);
  }
  return out;
}

std::string type_name(const toml::node& n) {
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
std::string show(const toml::node& n) {
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

// An allowed interval for a real value; non-finite values are always outside.
struct Range {
  double lo = -kInf, hi = kInf;
  bool lo_closed = true, hi_closed = true;

  bool contains(double v) const {
    return std::isfinite(v) && (lo_closed ? v >= lo : v > lo) && (hi_closed ? v <= hi : v < hi);
  }
  std::string text() const {
    if (lo == -kInf && hi == kInf) return "must be a finite number";
    if (hi == kInf) return fmt::format("must be {} {}", lo_closed ? ">=" : ">", lo);
    return fmt::format("must be in {}{}, {}{}", lo_closed ? '[' : '(', lo, hi, hi_closed ? ']' : ')');
  }
};
constexpr Range kPositive{0.0, kInf, false, true};
constexpr Range kNonNegative{0.0, kInf, true, true};
constexpr Range kFinite{};
constexpr Range kCutoff{0.0, 10.0, false, true};  // rc, rd and s share (0, 10]

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
      throw ConfigError(fmt::format("{}unknown key '{}'{}", at(key.source()), name(k), hint));
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
    throw ConfigError(fmt::format("{}{} = {}: {}", at(n.source()), name(key), show(n), why));
  }
  [[noreturn]] void bad(std::string_view key, std::string_view why) const { bad(key, *get(key), why); }
  [[noreturn]] void wrong_type(std::string_view key, const toml::node& n, std::string_view expected) const {
    bad(key, n, fmt::format("expected {}, got {}", expected, type_name(n)));
  }
  [[noreturn]] void missing(std::string_view key, std::string_view why = {}) const {
    throw ConfigError(fmt::format("{}missing required key '{}'{}", at(table_->source()), name(key), why));
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

  // Exactly three numbers, each inside `range`.
  std::optional<std::array<double, 3>> vec3(std::string_view key, Range range) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    const toml::array* arr = n->as_array();
    if (!arr) wrong_type(key, *n, "an array of 3 numbers");
    if (arr->size() != 3) bad(key, *n, fmt::format("expected 3 numbers, got {}", arr->size()));
    std::array<double, 3> out{};
    for (std::size_t d = 0; d < 3; ++d) {
      const toml::node& e = *arr->get(d);
      const std::string element = fmt::format("{}[{}]", key, d);
      if (const auto* f = e.as_floating_point()) {
        out[d] = f->get();
      } else if (const auto* i = e.as_integer()) {
        out[d] = static_cast<double>(i->get());
      } else {
        wrong_type(element, e, "a number");
      }
      if (!range.contains(out[d])) bad(element, e, range.text());
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

// ---------------------------------------------------------------------------------------------
// Typed, range-checked reads

std::optional<double> optional_real(const Section& s, std::string_view key, Range range) {
  const std::optional<double> v = s.real(key);
  if (v && !range.contains(*v)) s.bad(key, range.text());
  return v;
}

double real_or(const Section& s, std::string_view key, double fallback, Range range) {
  return optional_real(s, key, range).value_or(fallback);
}

std::optional<std::int64_t> optional_int(const Section& s, std::string_view key, std::int64_t lo,
                                         std::int64_t hi = std::numeric_limits<std::int64_t>::max()) {
  const std::optional<std::int64_t> v = s.integer(key);
  if (v && *v < lo) s.bad(key, fmt::format("must be an integer >= {}", lo));
  if (v && *v > hi) s.bad(key, fmt::format("must be an integer <= {}", hi));
  return v;
}

std::uint64_t uint_or(const Section& s, std::string_view key, std::uint64_t fallback, std::int64_t lo) {
  const auto v = optional_int(s, key, lo);
  return v ? static_cast<std::uint64_t>(*v) : fallback;
}

int int_or(const Section& s, std::string_view key, int fallback, int lo) {
  const auto v = optional_int(s, key, lo, INT_MAX);
  return v ? static_cast<int>(*v) : fallback;
}

// ---------------------------------------------------------------------------------------------
// Schema, one function per table

enum class Mixing { Explicit, Geometric };

// Pair parameters as written in [pair] or one [[pair.override]]; nullopt means "inherit".
struct PairKeys {
  std::optional<double> a, gamma, sigma, rc, rd, s;
};

PairKeys read_pair_keys(const Section& s) {
  PairKeys k;
  k.a = optional_real(s, "a", kNonNegative);
  k.gamma = optional_real(s, "gamma", kNonNegative);
  k.sigma = optional_real(s, "sigma", kNonNegative);
  k.rc = optional_real(s, "rc", kCutoff);
  k.rd = optional_real(s, "rd", kCutoff);
  k.s = optional_real(s, "s", kCutoff);
  return k;
}

void read_system(const Section& top, SimulationSpec& spec) {
  const Section sys = top.table_or_empty("system", {"box", "periodic", "kT", "seed"});
  const auto box = sys.vec3("box", kPositive);
  if (!box) sys.missing("box", " (three positive box lengths)");
  spec.box = *box;
  if (const auto periodic = sys.bool3("periodic")) {
    spec.periodic = *periodic;
    // The engine handles bounded axes, but until walls exist nothing would keep particles in.
    if (!(spec.periodic[0] && spec.periodic[1] && spec.periodic[2]))
      sys.bad("periodic",
              "a bounded axis (false) needs walls to close it, which are not implemented yet; use "
              "[true, true, true]");
  }
  spec.kT = real_or(sys, "kT", 1.0, kPositive);
  spec.seed = uint_or(sys, "seed", 1, 0);
}

void read_init(const Section& top, const fs::path& base_dir, SimulationSpec& spec) {
  const Section init = top.table_or_empty("init", {"lammps_data", "velocities"});
  if (const auto file = init.string("lammps_data")) {
    if (file->empty()) init.bad("lammps_data", "must be a non-empty path");
    const fs::path path = fs::absolute(base_dir / fs::path(*file)).lexically_normal();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      init.bad("lammps_data", fmt::format("no such file '{}'", path.string()));
    spec.data_file = path.string();
  }
  const bool has_data = !spec.data_file.empty();
  spec.velocities = init.choice<VelocityInit>("velocities", {{"maxwell", VelocityInit::Maxwell},
                                                             {"file", VelocityInit::File},
                                                             {"zero", VelocityInit::Zero}})
                        .value_or(has_data ? VelocityInit::File : VelocityInit::Maxwell);
  if (spec.velocities == VelocityInit::File && !has_data) {
    init.bad("velocities", "\"file\" needs init.lammps_data to read velocities from");
  }
  spec.init_velocities = spec.velocities == VelocityInit::Maxwell;
}

bool valid_species_name(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

void read_species(const Section& top, Mixing mixing, SimulationSpec& spec) {
  const std::vector<Section> list =
      top.tables("species", {"name", "mass", "a", "body_force", "density", "count", "placement"});
  if (list.empty()) top.missing("species", " (at least one [[species]] block is needed)");
  const bool from_data = !spec.data_file.empty();
  const double volume = spec.box[0] * spec.box[1] * spec.box[2];

  for (std::size_t k = 0; k < list.size(); ++k) {
    const Section& s = list[k];
    SpeciesSpec sp;
    const auto name = s.string("name");
    if (!name) s.missing("name");
    if (!valid_species_name(*name)) s.bad("name", "must be non-empty and use only letters, digits and '_'");
    for (std::size_t prev = 0; prev < k; ++prev) {
      if (spec.species[prev].name == *name) {
        s.bad("name", fmt::format("duplicate species name (also species[{}].name)", prev));
      }
    }
    sp.name = *name;
    sp.mass = real_or(s, "mass", 1.0, kPositive);

    sp.a = optional_real(s, "a", kNonNegative);
    if (mixing == Mixing::Geometric && !sp.a) {
      s.missing("a", " (pair.mixing = \"geometric\" needs a for every species)");
    }
    if (mixing == Mixing::Explicit && sp.a) {
      s.bad("a", "only used with pair.mixing = \"geometric\"; use pair.a or [[pair.override]] instead");
    }
    sp.body_force = s.vec3("body_force", kFinite).value_or(std::array<double, 3>{0, 0, 0});

    const auto density = optional_real(s, "density", kPositive);
    const auto count = optional_int(s, "count", 0);
    if (from_data) {
      // Positions, and so counts, come from the data file.
      for (const std::string_view key : {"density", "count", "placement"}) {
        if (s.has(key)) s.bad(key, "not allowed with init.lammps_data (particles come from the data file)");
      }
    } else {
      if (density && count)
        s.bad("count", fmt::format("give only one of {} and {}", s.name("density"), s.name("count")));
      if (!density && !count) s.missing("density", fmt::format(" (or {})", s.name("count")));
      if (density) {
        const double n = std::round(*density * volume);
        if (n > 1.0e15) s.bad("density", fmt::format("gives {:.3g} particles in the box; too many", n));
        sp.count = static_cast<std::uint64_t>(n);
      } else {
        sp.count = static_cast<std::uint64_t>(*count);
      }
    }
    sp.placement =
        s.choice<Placement>("placement", {{"random", Placement::Random}, {"lattice", Placement::Lattice}})
            .value_or(Placement::Random);
    spec.species.push_back(std::move(sp));
  }
}

// Resolves every unordered species pair: override > (geometric mixing for a | [pair]) > default.
void resolve_pairs(const Section& pair, const PairKeys& base, Mixing mixing, SimulationSpec& spec) {
  const std::size_t n = spec.species.size();
  const std::vector<Section> overrides =
      pair.tables("override", {"species", "a", "gamma", "sigma", "rc", "rd", "s"});
  std::vector<PairKeys> keys;
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> override_of(n * n, kNone);  // override index for (i, j), i <= j

  std::vector<std::string_view> names;
  for (const SpeciesSpec& sp : spec.species) names.push_back(sp.name);
  for (std::size_t k = 0; k < overrides.size(); ++k) {
    const Section& o = overrides[k];
    const auto pair_names = o.strings("species");
    if (!pair_names) o.missing("species", " (the two species names of the pair)");
    if (pair_names->size() != 2) o.bad("species", "must name exactly two species");
    std::array<std::size_t, 2> id{};
    for (std::size_t e = 0; e < 2; ++e) {
      const auto it = std::find(names.begin(), names.end(), (*pair_names)[e]);
      if (it == names.end()) {
        o.bad("species",
              fmt::format("unknown species \"{}\" (defined: {})", (*pair_names)[e], join(names, "\"")));
      }
      id[e] = static_cast<std::size_t>(it - names.begin());
    }
    std::size_t& slot = override_of[std::min(id[0], id[1]) * n + std::max(id[0], id[1])];
    if (slot != kNone)
      o.bad("species", fmt::format("this pair is already set by {}", overrides[slot].path()));
    slot = k;
    keys.push_back(read_pair_keys(o));
  }

  spec.pairs.clear();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i; j < n; ++j) {
      const std::size_t k = override_of[i * n + j];
      const PairKeys* ov = k != kNone ? &keys[k] : nullptr;
      const auto pick = [&](std::optional<double> PairKeys::*member) {
        return ov && (ov->*member) ? ov->*member : base.*member;
      };
      PairSpec p;
      p.i = static_cast<int>(i);
      p.j = static_cast<int>(j);
      if (ov && ov->a) {
        p.a = *ov->a;
      } else if (mixing == Mixing::Geometric) {
        p.a = std::sqrt(*spec.species[i].a * *spec.species[j].a);  // seed 002 Eq. 4
      } else {
        p.a = base.a.value_or(25.0);
      }
      p.gamma = pick(&PairKeys::gamma).value_or(4.5);
      p.rc = pick(&PairKeys::rc).value_or(1.0);
      p.rd = pick(&PairKeys::rd).value_or(p.rc);  // rd follows this pair's rc unless set
      p.s = pick(&PairKeys::s).value_or(2.0);

      // sigma is not independent: fluctuation-dissipation fixes sigma^2 = 2 gamma kT (seed 000 Eq. 7).
      if (const auto sigma = pick(&PairKeys::sigma)) {
        const Section& from = ov && ov->sigma ? overrides[k] : pair;
        const std::string gamma_key = ov && ov->gamma ? overrides[k].name("gamma") : pair.name("gamma");
        const double lhs = *sigma * *sigma, rhs = 2.0 * p.gamma * spec.kT;
        if (std::abs(lhs - rhs) > 1e-6 * std::max(lhs, rhs)) {
          from.bad("sigma",
                   fmt::format("inconsistent with {} = {} and system.kT = {} for species pair ({}, {}): "
                               "sigma^2 = 2 gamma kT requires sigma = {} (seed 000 Eq. 7)",
                               gamma_key, p.gamma, spec.kT, names[i], names[j], std::sqrt(rhs)));
        }
      }
      spec.pairs.push_back(p);
    }
  }
}

void read_integrator(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("integrator", {"type", "dt", "lambda"});
  spec.integrator = s.choice<IntegratorKind>("type", {{"groot-warren", IntegratorKind::GrootWarren},
                                                      {"euler", IntegratorKind::Euler}})
                        .value_or(IntegratorKind::GrootWarren);
  spec.dt = real_or(s, "dt", 0.04, Range{0.0, 0.5, false, true});
  spec.lambda = real_or(s, "lambda", 0.5, Range{0.0, 1.0, true, true});
  if (spec.integrator == IntegratorKind::Euler && s.has("lambda")) {
    s.bad("lambda", "only used by integrator.type = \"groot-warren\", not \"euler\"");
  }
}

void read_run(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("run", {"steps", "noise", "max_velocity", "threads"});
  spec.steps = uint_or(s, "steps", 1000, 0);
  spec.noise = s.choice<NoiseDistribution>("noise", {{"uniform", NoiseDistribution::Uniform},
                                                     {"gaussian", NoiseDistribution::Gaussian}})
                   .value_or(NoiseDistribution::Uniform);
  spec.max_velocity = real_or(s, "max_velocity", 1.0e3, kPositive);
  spec.threads = int_or(s, "threads", 0, 0);
}

void read_neighbor(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("neighbor", {"method", "skin"});
  spec.neighbor = s.choice<NeighborMethod>(
                       "method", {{"verlet", NeighborMethod::Verlet}, {"cells", NeighborMethod::Cells}})
                      .value_or(NeighborMethod::Cells);
  spec.skin = real_or(s, "skin", 0.3, Range{0.0, 2.0, true, true});
}

void read_parallel(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("parallel", {"grid"});
  if (const auto g = s.vec3("grid", Range{0.0, 65536.0, true, true})) {
    for (std::size_t d = 0; d < 3; ++d) {
      if ((*g)[d] != static_cast<double>(static_cast<int>((*g)[d])))
        s.bad("grid", fmt::format("element {} is {}, not a whole number of ranks (0 = choose)", d, (*g)[d]));
      spec.parallel_grid[d] = static_cast<int>((*g)[d]);
    }
  }
}

void read_output(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("output", {"thermo_every", "checkpoint_every", "progress", "dump"});
  spec.thermo_every = uint_or(s, "thermo_every", 100, 1);
  spec.checkpoint_every = uint_or(s, "checkpoint_every", 0, 0);
  spec.progress = s.boolean("progress").value_or(true);

  const auto dump = s.table("dump", {"format", "every", "fields", "file"});
  if (!dump) return;
  DumpSpec& d = spec.dump;
  d.enabled = true;
  d.format = dump->choice<DumpFormat>("format", {{"lammps", DumpFormat::Lammps}, {"gsd", DumpFormat::Gsd}})
                 .value_or(DumpFormat::Lammps);
  d.every = uint_or(*dump, "every", 1000, 1);
  if (auto fields = dump->strings("fields")) {
    static const std::vector<std::string_view> kFields{"id",       "species", "position",
                                                       "velocity", "force",   "image"};
    if (fields->empty())
      dump->bad("fields", fmt::format("must list at least one of {}", join(kFields, "\"")));
    for (std::size_t k = 0; k < fields->size(); ++k) {
      const std::string& f = (*fields)[k];
      if (std::find(kFields.begin(), kFields.end(), f) == kFields.end()) {
        dump->bad("fields", fmt::format("unknown field \"{}\" (allowed: {})", f, join(kFields, "\"")));
      }
      if (std::find(fields->begin(), fields->begin() + static_cast<std::ptrdiff_t>(k), f) !=
          fields->begin() + static_cast<std::ptrdiff_t>(k)) {
        dump->bad("fields", fmt::format("field \"{}\" is listed twice", f));
      }
    }
    d.fields = std::move(*fields);
  }
  if (auto file = dump->string("file")) {
    if (file->empty()) dump->bad("file", "must be a non-empty file name");
    d.file = std::move(*file);
  } else {
    d.file = d.format == DumpFormat::Gsd ? "trajectory.gsd" : "trajectory.lammpstrj";
  }
}

void read_poiseuille(const Section& top, SimulationSpec& spec) {
  const auto s =
      top.table("poiseuille", {"force", "flow_axis", "gradient_axis", "bins", "start", "every", "blocks"});
  if (!s) return;
  PoiseuilleSpec& p = spec.poiseuille;
  p.enabled = true;
  const auto force = optional_real(*s, "force", kFinite);
  if (!force) s->missing("force", " (the body acceleration g of reverse Poiseuille flow)");
  if (*force == 0.0) s->bad("force", "must be non-zero");
  p.force = *force;
  const std::initializer_list<std::pair<std::string_view, int>> axes{{"x", 0}, {"y", 1}, {"z", 2}};
  p.flow_axis = s->choice<int>("flow_axis", axes).value_or(0);
  p.gradient_axis = s->choice<int>("gradient_axis", axes).value_or(2);
  if (p.flow_axis == p.gradient_axis) {
    const std::string why =
        fmt::format("must differ from {} (\"{}\")", s->name("flow_axis"), "xyz"[p.flow_axis]);
    if (s->has("gradient_axis")) s->bad("gradient_axis", why);
    throw ConfigError(fmt::format("{}{} = \"z\" (default): {}", s->at(s->get("flow_axis")->source()),
                                  s->name("gradient_axis"), why));
  }
  p.bins = int_or(*s, "bins", 40, 4);
  if (p.bins % 2 != 0) s->bad("bins", "must be even (the two flow halves get equal bins)");
  p.start = uint_or(*s, "start", 0, 0);
  p.every = uint_or(*s, "every", 1, 1);
  p.blocks = int_or(*s, "blocks", 10, 2);
}

void read_analysis(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("analysis", {"rdf", "msd"});
  if (const auto rdf = s.table("rdf", {"bins", "rmax", "start", "every"})) {
    spec.rdf.enabled = true;
    spec.rdf.bins = int_or(*rdf, "bins", 100, 1);
    spec.rdf.rmax = real_or(*rdf, "rmax", 3.0, kPositive);
    const double half_box = 0.5 * std::min({spec.box[0], spec.box[1], spec.box[2]});
    if (!(spec.rdf.rmax < half_box)) {
      const std::string why = fmt::format("must be < half the smallest box length ({})", half_box);
      if (rdf->has("rmax")) rdf->bad("rmax", why);
      throw ConfigError(
          fmt::format("{}{} = {} (default): {}", rdf->at({}), rdf->name("rmax"), spec.rdf.rmax, why));
    }
    spec.rdf.start = uint_or(*rdf, "start", 0, 0);
    spec.rdf.every = uint_or(*rdf, "every", 100, 1);
  }
  if (const auto msd = s.table("msd", {"start", "every"})) {
    spec.msd.enabled = true;
    spec.msd.start = uint_or(*msd, "start", 0, 0);
    spec.msd.every = uint_or(*msd, "every", 100, 1);
  }
}

// Minimum image needs every box length to be at least twice the longest interaction range.
void check_box(const Section& top, const SimulationSpec& spec) {
  double cutoff = 0.0;
  for (const PairSpec& p : spec.pairs) cutoff = std::max({cutoff, p.rc, p.rd});
  for (int d = 0; d < 3; ++d) {
    if (spec.box[static_cast<std::size_t>(d)] < 2.0 * cutoff) {
      const Section sys = top.table_or_empty("system", {"box", "periodic", "kT", "seed"});
      sys.bad("box",
              fmt::format("every length must be >= 2 x the largest cutoff (max rc, rd = {}), i.e. >= {}",
                          cutoff, 2.0 * cutoff));
    }
  }
}

}  // namespace

SimulationSpec parse_config(std::string_view toml_text, const std::string& source_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("{}:{}:{}: TOML syntax error: {}", source_name, e.source().begin.line,
                                  e.source().begin.column, e.description()));
  }

  // Relative paths inside the file are relative to the file, not to wherever the program runs.
  fs::path base_dir = fs::path(source_name).parent_path();
  if (base_dir.empty()) base_dir = fs::current_path();

  const Section top(root, "",
                    {"system", "species", "pair", "integrator", "run", "neighbor", "init", "output",
                     "poiseuille", "analysis", "parallel"},
                    source_name);
  SimulationSpec spec;
  spec.source = source_name;
  read_system(top, spec);
  read_init(top, base_dir, spec);

  const Section pair =
      top.table_or_empty("pair", {"a", "gamma", "sigma", "rc", "rd", "s", "mixing", "override"});
  const Mixing mixing =
      pair.choice<Mixing>("mixing", {{"explicit", Mixing::Explicit}, {"geometric", Mixing::Geometric}})
          .value_or(Mixing::Explicit);
  const PairKeys base = read_pair_keys(pair);
  if (mixing == Mixing::Geometric && base.a) {
    pair.bad("a", "not used with pair.mixing = \"geometric\" (a_ij = sqrt(a_i a_j) from species[].a)");
  }
  read_species(top, mixing, spec);
  resolve_pairs(pair, base, mixing, spec);

  read_integrator(top, spec);
  read_run(top, spec);
  read_neighbor(top, spec);
  read_parallel(top, spec);
  read_output(top, spec);
  read_poiseuille(top, spec);
  read_analysis(top, spec);
  check_box(top, spec);
  return spec;
}

SimulationSpec load_config(const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec))
    throw ConfigError(fmt::format("{}: cannot read config file: no such file", file.string()));
  if (fs::is_directory(file, ec))
    throw ConfigError(fmt::format("{}: cannot read config file: is a directory", file.string()));
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw ConfigError(fmt::format("{}: cannot open config file: {}", file.string(), std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ConfigError(fmt::format("{}: error while reading config file", file.string()));
  return parse_config(text.str(), file.string());
}

}  // namespace mesodpd
