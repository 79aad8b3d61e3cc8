// TOML configuration -> SimulationSpec: unknown keys and types are checked here, ranges and derived
// defaults by validate(spec); every error names the full key and, where the file has it, file:line:col.
#include "mesodpd/config.hpp"

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
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "mesodpd/validate.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;

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
// The keys of a shape table ([[solid]] blocks add name, species and velocity).
const std::vector<std::string_view> kShapeKeys{"shape",   "point",   "normal", "center",     "direction",
                                               "radius",  "lo",      "hi",     "lattice",    "spacing",
                                               "axis",    "file",    "voxel_size", "invert", "parts"};

// Typed reads. Only what the spec's types cannot hold is refused here (a negative count, an int
// overflow); every range is validate()'s.

std::optional<std::int64_t> optional_int(const Section& s, std::string_view key, std::int64_t lo,
                                         std::int64_t hi = std::numeric_limits<std::int64_t>::max()) {
  const std::optional<std::int64_t> v = s.integer(key);
  if (v && *v < lo) s.bad(key, fmt::format("must be an integer >= {}", lo));
  if (v && *v > hi) s.bad(key, fmt::format("must be an integer <= {}", hi));
  return v;
}

void read_uint(const Section& s, std::string_view key, std::uint64_t& out) {
  if (const auto v = optional_int(s, key, 0)) out = static_cast<std::uint64_t>(*v);
}

void read_int(const Section& s, std::string_view key, int& out) {
  if (const auto v = optional_int(s, key, INT_MIN, INT_MAX)) out = static_cast<int>(*v);
}

void read_real(const Section& s, std::string_view key, double& out) {
  if (const auto v = s.real(key)) out = *v;
}

// ---------------------------------------------------------------------------------------------
// Schema, one function per table

PairParams read_pair_params(const Section& s) {
  PairParams k;
  k.a = s.real("a");
  k.gamma = s.real("gamma");
  k.sigma = s.real("sigma");
  k.rc = s.real("rc");
  k.rd = s.real("rd");
  k.s = s.real("s");
  k.b = s.real("b");
  k.repulsion = s.real("repulsion");
  k.rc1 = s.real("rc1");
  k.attraction = s.real("attraction");
  k.rc2 = s.real("rc2");
  return k;
}

void read_system(const Section& top, SimulationSpec& spec) {
  const Section sys = top.table_or_empty("system", {"box", "periodic", "kT", "seed"});
  const auto box = sys.vec3("box");
  if (!box) sys.missing("box", " (three positive box lengths)");
  spec.box = *box;
  if (const auto periodic = sys.bool3("periodic")) spec.periodic = *periodic;
  read_real(sys, "kT", spec.kT);
  read_uint(sys, "seed", spec.seed);
}

void read_init(const Section& top, const fs::path& base_dir, SimulationSpec& spec) {
  const Section init = top.table_or_empty("init", {"lammps_data", "velocities"});
  if (const auto file = init.string("lammps_data")) {
    if (file->empty()) init.bad("lammps_data", "must be a non-empty path");
    spec.data_file = fs::absolute(base_dir / fs::path(*file)).lexically_normal().string();
  }
  spec.velocities = init.choice<VelocityInit>("velocities", {{"maxwell", VelocityInit::Maxwell},
                                                             {"file", VelocityInit::File},
                                                             {"zero", VelocityInit::Zero}})
                        .value_or(spec.data_file.empty() ? VelocityInit::Maxwell : VelocityInit::File);
}

ShapeSpec read_shape(const Section& s, const fs::path& base_dir);

void read_species(const Section& top, const fs::path& base_dir, SimulationSpec& spec) {
  const std::vector<Section> list = top.tables(
      "species", {"name", "mass", "a", "body_force", "density", "count", "placement", "frozen", "region"});
  if (list.empty()) top.missing("species", " (at least one [[species]] block is needed)");
  const bool from_data = !spec.data_file.empty();
  for (const Section& s : list) {
    SpeciesSpec sp;
    const auto name = s.string("name");
    if (!name) s.missing("name");
    sp.name = *name;
    read_real(s, "mass", sp.mass);
    sp.a = s.real("a");
    sp.body_force = s.vec3("body_force").value_or(std::array<double, 3>{0, 0, 0});
    sp.density = s.real("density");
    const auto count = optional_int(s, "count", 0);
    sp.frozen = s.boolean("frozen").value_or(false);
    if (sp.frozen) {
      // Frozen (wall) particles are made by freezing the fluid inside [[solid]] blocks.
      for (const std::string_view key : {"count", "density", "placement", "region"})
        if (s.has(key)) s.bad(key, "not allowed for a frozen species (its particles are the fluid frozen inside [[solid]] blocks)");
    } else if (from_data) {
      // Positions, and so counts, come from the data file (validate() refuses a density; a count or
      // placement, even a zero or the default one, is refused here where its presence is known).
      for (const std::string_view key : {"count", "placement", "region"}) {
        if (s.has(key)) s.bad(key, "not allowed with init.lammps_data (particles come from the data file)");
      }
    } else {
      if (sp.density && count)
        s.bad("count", fmt::format("give only one of {} and {}", s.name("density"), s.name("count")));
      // A species used only in [[molecule]]s may leave both out (count 0).
      if (!sp.density && !count && !top.has("molecule"))
        s.missing("density", fmt::format(" (or {})", s.name("count")));
      if (count) sp.count = static_cast<std::uint64_t>(*count);
    }
    sp.placement =
        s.choice<Placement>("placement", {{"random", Placement::Random}, {"lattice", Placement::Lattice}})
            .value_or(Placement::Random);
    if (const auto region = s.table("region", kShapeKeys)) sp.region = read_shape(*region, base_dir);
    spec.species.push_back(std::move(sp));
  }
}

void read_pair(const Section& top, SimulationSpec& spec) {
  const Section pair = top.table_or_empty("pair", {"style", "a", "gamma", "sigma", "rc", "rd", "s", "b", "repulsion",
                                                   "rc1", "attraction", "rc2", "kernel", "mixing", "override"});
  spec.pair_style = pair.choice<PairStyle>("style", {{"dpd", PairStyle::Dpd},
                                                     {"soft", PairStyle::Soft},
                                                     {"mdpd", PairStyle::Mdpd},
                                                     {"spline", PairStyle::Spline}})
                        .value_or(PairStyle::Dpd);
  PairSection& sec = spec.pair_section;
  sec.kernel = pair.choice<DensityKernelChoice>("kernel", {{"warren", DensityKernelChoice::Warren},
                                                           {"lucy", DensityKernelChoice::Lucy}});
  sec.mixing = pair.choice<Mixing>("mixing", {{"explicit", Mixing::Explicit}, {"geometric", Mixing::Geometric}})
                   .value_or(Mixing::Explicit);
  sec.params = read_pair_params(pair);
  for (const Section& o : pair.tables("override", {"species", "a", "gamma", "sigma", "rc", "rd", "s", "b", "repulsion",
                                                  "rc1", "attraction", "rc2"})) {
    PairOverride ov;
    auto names = o.strings("species");
    if (!names) o.missing("species", " (the two species names of the pair)");
    ov.species = std::move(*names);
    ov.params = read_pair_params(o);
    sec.overrides.push_back(std::move(ov));
  }
}

// [[bond_type]], [[angle_type]], [[molecule]] and [bonds]: bonded interactions and the molecule builder.
void read_topology(const Section& top, SimulationSpec& spec) {
  for (const Section& s : top.tables("bond_type", {"name", "style", "k", "r0", "rmax", "persistence"})) {
    BondTypeSpec b;
    const auto name = s.string("name");
    if (!name) s.missing("name");
    b.name = *name;
    const auto style = s.choice<BondStyleSpec>(
        "style", {{"harmonic", BondStyleSpec::Harmonic}, {"fene", BondStyleSpec::Fene}, {"wlc", BondStyleSpec::Wlc}});
    if (!style) s.missing("style", " (\"harmonic\", \"fene\" or \"wlc\")");
    b.style = *style;
    // Each style reads its own keys; a key another style reads is refused rather than ignored.
    auto need = [&](std::string_view key, double& out) {
      const auto v = s.real(key);
      if (!v) s.missing(key, fmt::format(" (style \"{}\" needs it)", s.string("style").value_or("")));
      out = *v;
    };
    auto refuse = [&](std::string_view key) {
      if (s.has(key)) s.bad(key, fmt::format("not used by style \"{}\"", s.string("style").value_or("")));
    };
    switch (b.style) {
      case BondStyleSpec::Harmonic:
        need("k", b.k);
        read_real(s, "r0", b.r0);
        refuse("rmax");
        refuse("persistence");
        break;
      case BondStyleSpec::Fene:
        need("k", b.k);
        need("rmax", b.rmax);
        refuse("r0");
        refuse("persistence");
        break;
      case BondStyleSpec::Wlc:
        need("persistence", b.persistence);
        need("rmax", b.rmax);
        refuse("k");
        refuse("r0");
        break;
    }
    spec.bond_types.push_back(std::move(b));
  }
  for (const Section& s : top.tables("angle_type", {"name", "style", "k", "theta0"})) {
    AngleTypeSpec a;
    const auto name = s.string("name");
    if (!name) s.missing("name");
    a.name = *name;
    s.choice<int>("style", {{"cosine", 0}});
    const auto k = s.real("k");
    if (!k) s.missing("k");
    a.k = *k;
    read_real(s, "theta0", a.theta0_deg);
    spec.angle_types.push_back(std::move(a));
  }
  for (const Section& s : top.tables("molecule", {"name", "sequence", "bond_type", "angle_type", "count", "density",
                                                  "bond_length"})) {
    MoleculeSpec m;
    const auto name = s.string("name");
    if (!name) s.missing("name");
    m.name = *name;
    const auto seq = s.string("sequence");
    if (!seq) s.missing("sequence", " (e.g. \"A10\", \"H1T4\" or \"H3(T4)2\")");
    m.sequence = *seq;
    const auto bt = s.string("bond_type");
    if (!bt) s.missing("bond_type");
    m.bond_type = *bt;
    m.angle_type = s.string("angle_type").value_or("");
    m.density = s.real("density");
    const auto count = optional_int(s, "count", 0);
    if (m.density && count) s.bad("count", fmt::format("give only one of {} and {}", s.name("density"), s.name("count")));
    if (!m.density && !count) s.missing("count", fmt::format(" (or {})", s.name("density")));
    if (count) m.count = static_cast<std::uint64_t>(*count);
    read_real(s, "bond_length", m.bond_length);
    if (!spec.data_file.empty())
      s.bad("sequence", "not allowed with init.lammps_data (molecules come from the data file's Bonds section)");
    spec.molecules.push_back(std::move(m));
  }
  const Section bonds = top.table_or_empty("bonds", {"exclude", "reach", "subcycles"});
  spec.bond_reach_set = bonds.real("reach");
  spec.bond_subcycles = static_cast<int>(optional_int(bonds, "subcycles", 1, 1000).value_or(1));
  spec.bond_exclusion = bonds.choice<BondExclusion>("exclude", {{"none", BondExclusion::None},
                                                                {"1-2", BondExclusion::OneTwo},
                                                                {"1-3", BondExclusion::OneThree}})
                            .value_or(BondExclusion::None);
}

void read_integrator(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("integrator", {"type", "dt", "lambda"});
  spec.integrator = s.choice<IntegratorKind>("type", {{"groot-warren", IntegratorKind::GrootWarren},
                                                      {"euler", IntegratorKind::Euler}})
                        .value_or(IntegratorKind::GrootWarren);
  read_real(s, "dt", spec.dt);
  read_real(s, "lambda", spec.lambda);
  if (spec.integrator == IntegratorKind::Euler && s.has("lambda")) {
    s.bad("lambda", "only used by integrator.type = \"groot-warren\", not \"euler\"");
  }
}

void read_run(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("run", {"steps", "noise", "max_velocity", "max_density", "threads"});
  read_uint(s, "steps", spec.steps);
  spec.noise = s.choice<NoiseDistribution>("noise", {{"uniform", NoiseDistribution::Uniform},
                                                     {"gaussian", NoiseDistribution::Gaussian}})
                   .value_or(NoiseDistribution::Uniform);
  read_real(s, "max_velocity", spec.max_velocity);
  read_real(s, "max_density", spec.max_density);
  read_int(s, "threads", spec.threads);
}

void read_neighbor(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("neighbor", {"method", "skin"});
  spec.neighbor = s.choice<NeighborMethod>(
                       "method", {{"verlet", NeighborMethod::Verlet}, {"cells", NeighborMethod::Cells}})
                      .value_or(NeighborMethod::Cells);
  read_real(s, "skin", spec.skin);
}

void read_parallel(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("parallel", {"grid"});
  if (const auto g = s.vec3("grid")) {
    for (std::size_t d = 0; d < 3; ++d) {
      const double v = (*g)[d];
      if (!(std::abs(v) <= INT_MAX) || v != std::trunc(v))
        s.bad("grid", fmt::format("element {} is {}, not a whole number of ranks (0 = choose)", d, v));
      spec.parallel_grid[d] = static_cast<int>(v);
    }
  }
}

void read_output(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("output", {"thermo_every", "checkpoint_every", "progress", "dump"});
  read_uint(s, "thermo_every", spec.thermo_every);
  read_uint(s, "checkpoint_every", spec.checkpoint_every);
  spec.progress = s.boolean("progress").value_or(true);

  const auto dump = s.table("dump", {"format", "every", "fields", "file"});
  if (!dump) return;
  DumpSpec& d = spec.dump;
  d.enabled = true;
  d.format = dump->choice<DumpFormat>("format", {{"lammps", DumpFormat::Lammps}, {"gsd", DumpFormat::Gsd}})
                 .value_or(DumpFormat::Lammps);
  read_uint(*dump, "every", d.every);
  if (auto fields = dump->strings("fields")) d.fields = std::move(*fields);
  if (auto file = dump->string("file")) {
    // An empty name in the spec means "the default"; written in the file it is a mistake.
    if (file->empty()) dump->bad("file", "must be a non-empty file name");
    d.file = std::move(*file);
  }
}

void read_poiseuille(const Section& top, SimulationSpec& spec) {
  const auto s =
      top.table("poiseuille", {"force", "flow_axis", "gradient_axis", "bins", "start", "every", "blocks"});
  if (!s) return;
  PoiseuilleSpec& p = spec.poiseuille;
  p.enabled = true;
  const auto force = s->real("force");
  if (!force) s->missing("force", " (the body acceleration g of reverse Poiseuille flow)");
  p.force = *force;
  const std::initializer_list<std::pair<std::string_view, int>> axes{{"x", 0}, {"y", 1}, {"z", 2}};
  p.flow_axis = s->choice<int>("flow_axis", axes).value_or(0);
  p.gradient_axis = s->choice<int>("gradient_axis", axes).value_or(2);
  read_int(*s, "bins", p.bins);
  read_uint(*s, "start", p.start);
  read_uint(*s, "every", p.every);
  read_int(*s, "blocks", p.blocks);
}

// One shape table: a [[solid]] block or an element of its `parts`. Keys that the shape does not use
// are refused, so a cylinder's `radius` written under a plane is not silently ignored.
ShapeSpec read_shape(const Section& s, const fs::path& base_dir) {
  ShapeSpec sh;
  const auto kind = s.choice<ShapeKind>("shape", {{"plane", ShapeKind::Plane},
                                                   {"cylinder", ShapeKind::Cylinder},
                                                   {"sphere", ShapeKind::Sphere},
                                                   {"box", ShapeKind::Box},
                                                   {"pillars", ShapeKind::Pillars},
                                                   {"image", ShapeKind::Image},
                                                   {"union", ShapeKind::Union},
                                                   {"difference", ShapeKind::Difference}});
  if (!kind) s.missing("shape", " (plane, cylinder, sphere, box, pillars, image, union or difference)");
  sh.kind = *kind;
  std::vector<std::string_view> required, optional;
  switch (sh.kind) {
    case ShapeKind::Plane: required = {"point", "normal"}; break;
    case ShapeKind::Cylinder: required = {"center", "direction", "radius"}; break;
    case ShapeKind::Sphere: required = {"center", "radius"}; break;
    case ShapeKind::Box: required = {"lo", "hi"}; break;
    case ShapeKind::Pillars: required = {"lattice", "spacing", "radius"}, optional = {"axis", "point"}; break;
    case ShapeKind::Image: required = {"file", "voxel_size"}, optional = {"axis", "invert"}; break;
    case ShapeKind::Union:
    case ShapeKind::Difference: required = {"parts"}; break;
  }
  const std::vector<std::string_view> shape_keys{"point", "normal", "center", "direction", "radius", "lo", "hi",
                                                 "lattice", "spacing", "axis", "file", "voxel_size", "invert", "parts"};
  for (const std::string_view key : shape_keys) {
    const bool needed = std::find(required.begin(), required.end(), key) != required.end();
    const bool allowed = needed || std::find(optional.begin(), optional.end(), key) != optional.end();
    if (s.has(key) && !allowed) s.bad(key, fmt::format("not used by {} = {}", s.name("shape"), show(*s.get("shape"))));
    if (!s.has(key) && needed) s.missing(key, fmt::format(" (needed by {} = {})", s.name("shape"), show(*s.get("shape"))));
  }
  if (auto v = s.vec3("point")) sh.point = *v;
  if (auto v = s.vec3("normal")) sh.normal = *v;
  if (auto v = s.vec3("center")) sh.center = *v;
  if (auto v = s.vec3("direction")) sh.direction = *v;
  if (auto v = s.vec3("lo")) sh.lo = *v;
  if (auto v = s.vec3("hi")) sh.hi = *v;
  read_real(s, "radius", sh.radius);
  read_real(s, "spacing", sh.spacing);
  read_real(s, "voxel_size", sh.voxel_size);
  sh.lattice = s.choice<Lattice>("lattice", {{"square", Lattice::Square}, {"hexagonal", Lattice::Hexagonal}})
                   .value_or(Lattice::Square);
  sh.axis = s.choice<int>("axis", {{"x", 0}, {"y", 1}, {"z", 2}}).value_or(2);
  sh.invert = s.boolean("invert").value_or(false);
  if (const auto file = s.string("file")) {
    if (file->empty()) s.bad("file", "must be a non-empty path");
    sh.file = fs::absolute(base_dir / fs::path(*file)).lexically_normal().string();
  }
  for (const Section& part : s.tables("parts", kShapeKeys)) sh.parts.push_back(read_shape(part, base_dir));
  if (s.has("parts") && sh.parts.empty()) s.bad("parts", "needs at least one shape table");
  return sh;
}

void read_solids(const Section& top, const fs::path& base_dir, SimulationSpec& spec) {
  std::vector<std::string_view> keys = kShapeKeys;
  for (const std::string_view k : {"name", "species", "velocity"}) keys.push_back(k);
  for (const Section& s : top.tables("solid", keys)) {
    SolidSpec solid;
    const auto name = s.string("name");
    if (!name) s.missing("name");
    solid.name = *name;
    const auto species = s.string("species");
    if (!species) s.missing("species", " (the frozen species its particles become)");
    solid.species = *species;
    solid.velocity = s.vec3("velocity").value_or(std::array<double, 3>{0, 0, 0});
    solid.shape = read_shape(s, base_dir);
    spec.solids.push_back(std::move(solid));
  }
  const auto w = top.table("walls", {"reflection", "layer", "depth", "equilibrate", "drag_start", "drag_every", "drag_blocks",
                                     "reference_length", "reference_area", "viscosity", "adaptive", "adaptive_bins",
                                     "adaptive_range", "adaptive_gain", "adaptive_every", "adaptive_stop"});
  if (!w) return;
  WallsSpec& ws = spec.walls;
  ws.reflection = w->choice<ReflectionKind>("reflection", {{"none", ReflectionKind::None},
                                                           {"specular", ReflectionKind::Specular},
                                                           {"bounce_back", ReflectionKind::BounceBack},
                                                           {"maxwell", ReflectionKind::Maxwell}})
                      .value_or(ReflectionKind::BounceBack);
  read_real(*w, "layer", ws.layer);
  read_real(*w, "depth", ws.depth);
  read_uint(*w, "equilibrate", ws.equilibrate);
  read_uint(*w, "drag_start", ws.drag_start);
  read_uint(*w, "drag_every", ws.drag_every);
  read_int(*w, "drag_blocks", ws.drag_blocks);
  read_real(*w, "reference_length", ws.reference_length);
  read_real(*w, "reference_area", ws.reference_area);
  read_real(*w, "viscosity", ws.viscosity);
  ws.adaptive = w->boolean("adaptive").value_or(false);
  read_int(*w, "adaptive_bins", ws.adaptive_bins);
  read_real(*w, "adaptive_range", ws.adaptive_range);
  read_real(*w, "adaptive_gain", ws.adaptive_gain);
  read_uint(*w, "adaptive_every", ws.adaptive_every);
  read_uint(*w, "adaptive_stop", ws.adaptive_stop);
}

void read_fields(const Section& f, SimulationSpec& spec) {
  FieldsSpec& out = spec.fields.emplace_back();
  if (auto name = f.string("name")) out.name = std::move(*name);
  if (const auto b = f.vec3("bins")) {
    for (std::size_t d = 0; d < 3; ++d) {
      const double v = (*b)[d];
      if (!(std::abs(v) <= INT_MAX) || v != std::trunc(v))
        f.bad("bins", fmt::format("element {} is {}, not a whole number of bins", d, v));
      out.bins[d] = static_cast<int>(v);
    }
  }
  out.lo = f.vec3("lo");
  out.hi = f.vec3("hi");
  read_uint(f, "start", out.start);
  read_uint(f, "every", out.every);
  if (auto sp = f.strings("species")) out.species = std::move(*sp);
  if (auto ex = f.strings("exclude")) out.exclude = std::move(*ex);
  out.centre_axis = f.choice<int>("centre", {{"none", -1}, {"x", 0}, {"y", 1}, {"z", 2}}).value_or(-1);
  read_int(f, "blocks", out.blocks);
  read_uint(f, "write_every", out.write_every);
  out.fit = f.choice<FieldsFit>("fit", {{"none", FieldsFit::None}, {"slab", FieldsFit::Slab}}).value_or(FieldsFit::None);
}

void read_analysis(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("analysis", {"rdf", "msd", "fields", "surface_tension", "droplet", "stress_profile"});
  // [analysis.fields] once, or [[analysis.fields]] for several grids in one run.
  const std::vector<std::string_view> kFieldKeys{"name", "bins", "lo", "hi", "start", "every",
                                                 "species", "exclude", "centre", "fit", "blocks", "write_every"};
  if (const toml::node* n = s.get("fields"); n && n->is_table()) {
    read_fields(*s.table("fields", kFieldKeys), spec);
  } else if (n) {
    for (const Section& f : s.tables("fields", kFieldKeys)) read_fields(f, spec);
  }
  if (const auto rdf = s.table("rdf", {"bins", "rmax", "start", "every"})) {
    spec.rdf.enabled = true;
    read_int(*rdf, "bins", spec.rdf.bins);
    read_real(*rdf, "rmax", spec.rdf.rmax);
    read_uint(*rdf, "start", spec.rdf.start);
    read_uint(*rdf, "every", spec.rdf.every);
  }
  if (const auto msd = s.table("msd", {"start", "every"})) {
    spec.msd.enabled = true;
    read_uint(*msd, "start", spec.msd.start);
    read_uint(*msd, "every", spec.msd.every);
  }
  if (const auto st = s.table("surface_tension", {"axis", "start", "blocks"})) {
    SurfaceTensionSpec& t = spec.surface_tension;
    t.enabled = true;
    t.axis = st->choice<int>("axis", {{"x", 0}, {"y", 1}, {"z", 2}}).value_or(2);
    read_uint(*st, "start", t.start);
    read_int(*st, "blocks", t.blocks);
  }
  if (const auto d = s.table("droplet", {"start", "every", "inner_radius", "outer_radius", "bin_width", "blocks"})) {
    DropletSpec& o = spec.droplet;
    o.enabled = true;
    read_uint(*d, "start", o.start);
    read_uint(*d, "every", o.every);
    read_real(*d, "inner_radius", o.inner_radius);
    read_real(*d, "outer_radius", o.outer_radius);
    read_real(*d, "bin_width", o.bin_width);
    read_int(*d, "blocks", o.blocks);
  }
  if (const auto d = s.table("stress_profile", {"axis", "bins", "start", "every", "blocks", "assignment"})) {
    StressProfileSpec& o = spec.stress_profile;
    o.enabled = true;
    o.axis = d->choice<int>("axis", {{"x", 0}, {"y", 1}, {"z", 2}}).value_or(2);
    read_int(*d, "bins", o.bins);
    read_uint(*d, "start", o.start);
    read_uint(*d, "every", o.every);
    read_int(*d, "blocks", o.blocks);
    o.assignment = d->choice<StressAssignment>("assignment", {{"contour", StressAssignment::Contour},
                                                              {"half", StressAssignment::Half}})
                       .value_or(StressAssignment::Contour);
  }
}

// Where each key of the file is: "system.box", "system.box[2]", "pair.override[1].rd", ... as
// validate() names them, so its errors get the file:line:col of the key they name.
using Positions = std::map<std::string, toml::source_region, std::less<>>;

void record_positions(const toml::node& node, const std::string& name, Positions& out) {
  if (!name.empty()) out.emplace(name, node.source());
  if (const toml::table* t = node.as_table()) {
    for (const auto& [key, value] : *t)
      record_positions(value, name.empty() ? std::string(key.str()) : fmt::format("{}.{}", name, key.str()), out);
  } else if (const toml::array* a = node.as_array()) {
    for (std::size_t k = 0; k < a->size(); ++k) record_positions(*a->get(k), fmt::format("{}[{}]", name, k), out);
  }
}

// validate()'s error with the position of its key, or of the nearest enclosing table written in the
// file; a value the file does not set is marked "(default)".
ConfigError located(const SpecError& e, const Positions& positions, const std::string& source) {
  const auto written = positions.find(e.key());
  std::string_view scope = e.key();
  auto at = written;
  while (at == positions.end() && !scope.empty()) {
    const std::size_t cut = scope.find_last_of(".[");
    scope = cut == std::string_view::npos ? std::string_view{} : scope.substr(0, cut);
    if (!scope.empty()) at = positions.find(scope);
  }
  std::string where = source + ": ";
  if (at != positions.end() && at->second.begin.line != 0)
    where = fmt::format("{}:{}:{}: ", source, at->second.begin.line, at->second.begin.column);
  if (e.value().empty()) return ConfigError(fmt::format("{}{}: {}", where, e.key(), e.why()), e.key());
  return ConfigError(fmt::format("{}{} = {}{}: {}", where, e.key(), e.value(),
                                 written == positions.end() ? " (default)" : "", e.why()),
                     e.key());
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
                     "poiseuille", "analysis", "parallel", "solid", "walls", "bond_type", "angle_type",
                     "molecule", "bonds"},
                    source_name);
  SimulationSpec spec;
  spec.source = source_name;
  read_system(top, spec);
  read_init(top, base_dir, spec);
  read_species(top, base_dir, spec);
  read_pair(top, spec);
  read_topology(top, spec);
  read_integrator(top, spec);
  read_run(top, spec);
  read_neighbor(top, spec);
  read_parallel(top, spec);
  read_output(top, spec);
  read_poiseuille(top, spec);
  read_analysis(top, spec);
  read_solids(top, base_dir, spec);
  try {
    validate(spec);
  } catch (const SpecError& e) {
    Positions positions;
    record_positions(root, "", positions);
    throw located(e, positions, source_name);
  }
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
