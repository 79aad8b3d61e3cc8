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
#include "analysis/analysis_keys.hpp"
#include "boundary/boundary_keys.hpp"
#include "engine/bonded_keys.hpp"
#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/run_keys.hpp"
#include "integrate/integrator_keys.hpp"
#include "schema/section.hpp"
#include "schema/species_keys.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;
using namespace schema;

// The keys of a shape table: a [[solid]] block's (with the solid's own), an element of `parts`, a region.
std::vector<std::string_view> shape_names() { return shape_keys().names(); }

// ---------------------------------------------------------------------------------------------
// Schema, one function per table

// The keys of a [pair] or [[pair.override]] table: the shared DPD keys and every law's own keys (the
// style's law refuses the keys it does not read, in validate()).
std::vector<std::string_view> pair_param_names() {
  std::vector<std::string_view> names(kSharedPairKeys.begin(), kSharedPairKeys.end());
  for (const PairLawInfo& law : pair_law_infos())
    for (const LawKey& k : law.own)
      if (std::find(names.begin(), names.end(), k.name) == names.end()) names.push_back(k.name);
  return names;
}

PairParams read_pair_params(const Section& s) {
  PairParams k;
  k.a = s.real("a");
  k.gamma = s.real("gamma");
  k.sigma = s.real("sigma");
  k.rc = s.real("rc");
  k.rd = s.real("rd");
  k.s = s.real("s");
  for (const std::string_view name : pair_param_names())
    if (std::find(kSharedPairKeys.begin(), kSharedPairKeys.end(), name) == kSharedPairKeys.end())
      if (const auto v = s.real(name)) k.own.emplace(std::string(name), *v);
  return k;
}

void read_system(const Section& top, SimulationSpec& spec) {
  const Section sys = top.table_or_empty("system", system_keys().names());
  read_keys(system_keys(), sys, spec);
}

void read_init(const Section& top, const fs::path& base_dir, SimulationSpec& spec) {
  const Section init = top.table_or_empty("init", init_keys().names());
  if (const auto file = init.string("lammps_data")) {
    if (file->empty()) init.bad("lammps_data", "must be a non-empty path");
    spec.data_file = fs::absolute(base_dir / fs::path(*file)).lexically_normal().string();
  }
  spec.velocities = spec.data_file.empty() ? VelocityInit::Maxwell : VelocityInit::File;
  read_keys(init_keys(), init, spec);
}

ShapeSpec read_shape(const Section& s, const fs::path& base_dir);

// The keys of a [[species]] block: the table's and every pair law's species keys (the style's law
// refuses those it does not read, in validate()).
std::vector<std::string_view> species_names() {
  std::vector<std::string_view> names = species_keys().names();
  for (const PairLawInfo& law : pair_law_infos())
    for (const LawKey& k : law.species_own)
      if (std::find(names.begin(), names.end(), k.name) == names.end()) names.push_back(k.name);
  return names;
}

void read_species(const Section& top, const fs::path& base_dir, SimulationSpec& spec) {
  const std::vector<std::string_view> names = species_names();
  const std::vector<Section> list = top.tables("species", names);
  if (list.empty()) top.missing("species", " (at least one [[species]] block is needed)");
  const bool from_data = !spec.data_file.empty();
  for (const Section& s : list) {
    SpeciesSpec sp;
    read_keys(species_keys(), s, sp);
    for (std::size_t k = species_keys().names().size(); k < names.size(); ++k)
      if (const auto v = s.real(names[k])) sp.own.emplace(std::string(names[k]), *v);
    // Which keys go together depends on the other tables: a frozen species, a data file, molecules.
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
      if (sp.density && s.has("count"))
        s.bad("count", fmt::format("give only one of {} and {}", s.name("density"), s.name("count")));
      // A species used only in [[molecule]]s may leave both out (count 0).
      if (!sp.density && !s.has("count") && !top.has("molecule"))
        s.missing("density", fmt::format(" (or {})", s.name("count")));
    }
    if (const auto region = s.table("region", shape_names())) sp.region = read_shape(*region, base_dir);
    spec.species.push_back(std::move(sp));
  }
}

void read_pair(const Section& top, SimulationSpec& spec) {
  std::vector<std::string_view> keys{"style"};
  for (const std::string_view k : pair_param_names()) keys.push_back(k);
  for (const std::string_view k : {"kernel", "mixing", "override"}) keys.push_back(k);
  const Section pair = top.table_or_empty("pair", keys);
  std::vector<std::pair<std::string, int>> styles;
  for (const PairLawInfo& law : pair_law_infos()) styles.emplace_back(std::string(law.style), static_cast<int>(styles.size()));
  spec.pair_style = static_cast<PairStyle>(pair.choice_of("style", styles).value_or(0));
  PairSection& sec = spec.pair_section;
  sec.kernel = pair.choice<DensityKernelChoice>("kernel", {{"warren", DensityKernelChoice::Warren},
                                                           {"lucy", DensityKernelChoice::Lucy},
                                                           {"wendland", DensityKernelChoice::Wendland}});
  sec.mixing = pair.choice<Mixing>("mixing", {{"explicit", Mixing::Explicit}, {"geometric", Mixing::Geometric}})
                   .value_or(Mixing::Explicit);
  sec.params = read_pair_params(pair);
  std::vector<std::string_view> override_keys{"species"};
  for (const std::string_view k : pair_param_names()) override_keys.push_back(k);
  for (const Section& o : pair.tables("override", override_keys)) {
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
  for (const Section& s : top.tables("bond_type", bond_type_keys().names()))
    read_keys(bond_type_keys(), s, spec.bond_types.emplace_back());
  for (const Section& s : top.tables("angle_type", angle_type_keys().names()))
    read_keys(angle_type_keys(), s, spec.angle_types.emplace_back());
  for (const Section& s : top.tables("dihedral_type", dihedral_type_keys().names()))
    read_keys(dihedral_type_keys(), s, spec.dihedral_types.emplace_back());
  for (const Section& s : top.tables("molecule", molecule_keys().names())) {
    MoleculeSpec& m = spec.molecules.emplace_back();
    read_keys(molecule_keys(), s, m);
    if (m.density && s.has("count")) s.bad("count", fmt::format("give only one of {} and {}", s.name("density"), s.name("count")));
    if (!m.density && !s.has("count")) s.missing("count", fmt::format(" (or {})", s.name("density")));
    if (!spec.data_file.empty())
      s.bad("sequence", "not allowed with init.lammps_data (molecules come from the data file's Bonds section)");
  }
  read_keys(bonds_keys(), top.table_or_empty("bonds", bonds_keys().names()), spec);
}

void read_integrator(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("integrator", integrator_keys().names());
  read_keys(integrator_keys(), s, spec);
  if (spec.integrator == IntegratorKind::Euler && s.has("lambda")) {
    s.bad("lambda", "only used by integrator.type = \"groot-warren\", not \"euler\"");
  }
}

void read_run(const Section& top, SimulationSpec& spec) {
  read_keys(run_keys(), top.table_or_empty("run", run_keys().names()), spec);
}

void read_neighbor(const Section& top, SimulationSpec& spec) {
  read_keys(neighbor_keys(), top.table_or_empty("neighbor", neighbor_keys().names()), spec);
}

void read_parallel(const Section& top, SimulationSpec& spec) {
  read_keys(parallel_keys(), top.table_or_empty("parallel", parallel_keys().names()), spec);
}

void read_output(const Section& top, SimulationSpec& spec) {
  const Section s = top.table_or_empty("output", output_keys().names());
  read_keys(output_keys(), s, spec);
  const auto dump = s.table("dump", dump_keys().names());
  if (!dump) return;
  DumpSpec& d = spec.dump;
  d.enabled = true;
  read_keys(dump_keys(), *dump, d);
  // An empty name in the spec means "the default"; written in the file it is a mistake.
  if (dump->has("file") && d.file.empty()) dump->bad("file", "must be a non-empty file name");
}

void read_poiseuille(const Section& top, SimulationSpec& spec) {
  const auto s = top.table("poiseuille", poiseuille_keys().names());
  if (!s) return;
  spec.poiseuille.enabled = true;
  read_keys(poiseuille_keys(), *s, spec.poiseuille);
}

// One shape table: a [[solid]] block or an element of its `parts`. Keys that the shape does not use
// are refused (shape_keys() says which keys each shape reads), so a cylinder's `radius` written under a
// plane is not silently ignored.
ShapeSpec read_shape(const Section& s, const fs::path& base_dir) {
  ShapeSpec sh;
  read_keys(shape_keys(), s, sh);
  if (s.has("file")) {
    if (sh.file.empty()) s.bad("file", "must be a non-empty path");
    sh.file = fs::absolute(base_dir / fs::path(sh.file)).lexically_normal().string();
  }
  for (const Section& part : s.tables("parts", shape_names())) sh.parts.push_back(read_shape(part, base_dir));
  if (s.has("parts") && sh.parts.empty()) s.bad("parts", "needs at least one shape table");
  return sh;
}

void read_solids(const Section& top, const fs::path& base_dir, SimulationSpec& spec) {
  // The shape's keys first: the order of the list that an unknown key's message gives.
  std::vector<std::string_view> keys = shape_names();
  for (const std::string_view k : solid_keys().names()) keys.push_back(k);
  for (const Section& s : top.tables("solid", keys)) {
    SolidSpec& solid = spec.solids.emplace_back();
    read_keys(solid_keys(), s, solid);
    solid.shape = read_shape(s, base_dir);
  }
  const auto w = top.table("walls", walls_keys().names());
  if (w) read_keys(walls_keys(), *w, spec.walls);
}

// Each [analysis.fields] or [[analysis.fields]] grid.
void read_fields(const Section& f, SimulationSpec& spec) { read_keys(fields_keys(), f, spec.fields.emplace_back()); }

// The tables a table may hold: the schema's own, then those the model sections add under it (a model's
// [analysis.x] or [x], engine/installer.hpp).
std::vector<std::string_view> allowed_tables(std::vector<std::string_view> own, std::string_view parent,
                                             const std::vector<ModelSection>& models) {
  for (const ModelSection& m : models) {
    const std::string_view path = m.path;
    std::string_view child;
    if (parent.empty()) {
      child = path.substr(0, path.find('.'));
    } else if (path.size() > parent.size() && path.starts_with(parent) && path[parent.size()] == '.') {
      child = path.substr(parent.size() + 1);
      child = child.substr(0, child.find('.'));
    }
    if (!child.empty() && std::find(own.begin(), own.end(), child) == own.end()) own.push_back(child);
  }
  return own;
}

// The top-level tables the schema reads itself, and those it reads inside [analysis].
const std::vector<std::string_view> kSchemaTables{"system", "species",  "pair",  "integrator", "run",       "neighbor",
                                                  "init",   "output",   "poiseuille", "analysis", "parallel", "solid",
                                                  "walls",  "bond_type", "angle_type", "dihedral_type", "molecule", "bonds"};
const std::vector<std::string_view> kAnalysisTables{"rdf", "msd", "fields", "surface_tension", "droplet", "stress_profile"};

// Each model section the file writes, read through the model's declared keys into spec.models. A
// section is [name] or [parent.name], where parent is "analysis" or a table of models alone.
void read_models(const Section& top, const std::vector<ModelSection>& models, SimulationSpec& spec) {
  for (const ModelSection& m : models) {
    const std::vector<std::string_view> names(m.names.begin(), m.names.end());
    std::optional<Section> at;
    const std::size_t dot = m.path.find('.');
    const std::string parent = m.path.substr(0, dot);
    const auto listed = [](const std::vector<std::string_view>& list, std::string_view name) {
      return std::find(list.begin(), list.end(), name) != list.end();
    };
    // A model's section is a table of its own: a new [name], [analysis.name] beside the schema's
    // analyses, or [parent.name] under a table that only models use.
    const bool own_table =
        dot == std::string::npos
            ? !listed(kSchemaTables, parent)
            : m.path.find('.', dot + 1) == std::string::npos &&
                  (parent == "analysis" ? !listed(kAnalysisTables, m.path.substr(dot + 1)) : !listed(kSchemaTables, parent));
    if (!own_table)
      throw std::logic_error("model section [" + m.path + "]: a model's section must be a new [name], [analysis.name] "
                             "or [parent.name] under a table that only models use");
    if (m.gather) {  // [[name]] blocks (a repeatable section is a top-level table)
      if (dot != std::string::npos)
        throw std::logic_error("model section [[" + m.path + "]]: a repeatable section must be a top-level [[name]]");
      std::vector<std::any> items;
      for (const Section& t : top.tables(m.path, names)) items.push_back(m.read(schema::SectionReader(t)));
      if (!items.empty()) spec.models[m.path] = m.gather(std::move(items));
      continue;
    }
    if (dot == std::string::npos) {
      at = top.table(m.path, names);
    } else {
      if (!top.has(parent)) continue;
      const std::vector<std::string_view> own =
          parent == "analysis" ? kAnalysisTables : std::vector<std::string_view>{};
      at = top.table(parent, allowed_tables(own, parent, models))->table(m.path.substr(dot + 1), names);
    }
    if (at) spec.models[m.path] = m.read(schema::SectionReader(*at));
  }
}

void read_analysis(const Section& top, const std::vector<ModelSection>& models, SimulationSpec& spec) {
  const Section s = top.table_or_empty("analysis", allowed_tables(kAnalysisTables, "analysis", models));
  // [analysis.fields] once, or [[analysis.fields]] for several grids in one run.
  if (const toml::node* n = s.get("fields"); n && n->is_table()) {
    read_fields(*s.table("fields", fields_keys().names()), spec);
  } else if (n) {
    for (const Section& f : s.tables("fields", fields_keys().names())) read_fields(f, spec);
  }
  // A sub-table whose presence turns its analysis on, read into `out` from the keys it declares.
  const auto optional_table = [&](const auto& table, std::string_view name, auto& out) {
    if (const auto t = s.table(name, table.names())) {
      out.enabled = true;
      read_keys(table, *t, out);
    }
  };
  optional_table(rdf_keys(), "rdf", spec.rdf);
  optional_table(msd_keys(), "msd", spec.msd);
  optional_table(surface_tension_keys(), "surface_tension", spec.surface_tension);
  optional_table(droplet_keys(), "droplet", spec.droplet);
  optional_table(stress_profile_keys(), "stress_profile", spec.stress_profile);
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

  std::vector<ModelSection> models;
  for (const Model& m : mesodpd::models())
    if (m.section) models.push_back(m.section());
  const Section top(root, "",
                    allowed_tables(kSchemaTables, "", models),
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
  read_analysis(top, models, spec);
  read_solids(top, base_dir, spec);
  read_models(top, models, spec);
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
