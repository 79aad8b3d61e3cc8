// The list of declared key tables (one entry per table of the schema and per model section), for the
// docs, their test and `mesodpd check`'s summary.
#include "schema/declared_tables.hpp"

#include "analysis/analysis_keys.hpp"
#include "boundary/boundary_keys.hpp"
#include "engine/bonded_keys.hpp"
#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/run_keys.hpp"
#include "integrate/integrator_keys.hpp"
#include "schema/species_keys.hpp"

namespace mesodpd {

namespace {

using Values = DeclaredTable::Values;

// A table read once: its values when `of` gives them (nullptr: the file leaves the table out), shown only
// where some differ from the defaults unless `always` (a table whose presence turns its model on).
template <class T>
DeclaredTable one(const keys::KeyTable<T>& table, const T* (*of)(const SimulationSpec&), bool always = false) {
  DeclaredTable t{table.path(), table.docs()};
  t.values = [&table, of, always](const SimulationSpec& spec) {
    Values out;
    if (const T* v = of(spec)) {
      std::vector<std::string> set = table.set_values(*v);
      if (!set.empty() || always) out.emplace_back(table.path(), std::move(set));
    }
    return out;
  };
  return t;
}

// A table written as [[path]] blocks: each block's values, named path[k].
template <class T>
DeclaredTable each(const keys::KeyTable<T>& table, const std::vector<T>& (*of)(const SimulationSpec&),
                   std::string minimal) {
  DeclaredTable t{table.path(), table.docs(), true, std::move(minimal)};
  t.values = [&table, of](const SimulationSpec& spec) {
    Values out;
    const std::vector<T>& list = of(spec);
    for (std::size_t k = 0; k < list.size(); ++k)
      out.emplace_back(table.path() + "[" + std::to_string(k) + "]", table.set_values(list[k]));
    return out;
  };
  return t;
}

const SimulationSpec* whole(const SimulationSpec& s) { return &s; }

}  // namespace

std::vector<DeclaredTable> declared_tables() {
  std::vector<DeclaredTable> out;
  out.push_back(one(system_keys(), whole));
  {
    // [[species]] blocks hold the table's keys and the pair laws' species keys (set where not a default).
    DeclaredTable t = each(species_keys(), +[](const SimulationSpec& s) -> const auto& { return s.species; },
                           "name = \"A\"\ndensity = 3");
    for (keys::KeyDoc& row : pair_species_key_docs()) t.rows.push_back(std::move(row));
    t.values = [](const SimulationSpec& spec) {
      Values out;
      const PairLawInfo& law = pair_law(spec.pair_style);
      for (std::size_t k = 0; k < spec.species.size(); ++k) {
        std::vector<std::string> set = species_keys().set_values(spec.species[k]);
        for (const LawKey& key : law.species_own)
          if (const auto it = spec.species[k].own.find(key.name);
              it != spec.species[k].own.end() && (key.required || it->second != key.fallback))
            set.push_back(std::string(key.name) + " = " + keys::doc_number(it->second));
        out.emplace_back("species[" + std::to_string(k) + "]", std::move(set));
      }
      return out;
    };
    out.push_back(std::move(t));
  }
  out.push_back({"pair", pair_key_docs()});
  out.push_back({"pair.override", pair_override_key_docs(), true, "species = [\"A\", \"A\"]"});
  out.push_back(one(integrator_keys(), whole));
  out.push_back(one(run_keys(), whole));
  out.push_back(one(neighbor_keys(), whole));
  out.push_back(one(parallel_keys(), whole));
  out.push_back(each(bond_type_keys(), +[](const SimulationSpec& s) -> const auto& { return s.bond_types; },
                     "name = \"b\"\nstyle = \"harmonic\"\nk = 1"));
  out.push_back(each(angle_type_keys(), +[](const SimulationSpec& s) -> const auto& { return s.angle_types; },
                     "name = \"t\"\nk = 1"));
  out.push_back(each(dihedral_type_keys(), +[](const SimulationSpec& s) -> const auto& { return s.dihedral_types; },
                     "name = \"d\"\nk = 1"));
  out.push_back(each(molecule_keys(), +[](const SimulationSpec& s) -> const auto& { return s.molecules; },
                     "name = \"m\"\nsequence = \"A2\"\nbond_type = \"b\"\ncount = 1"));
  out.push_back(one(bonds_keys(), whole));
  out.push_back(one(init_keys(), whole));
  out.push_back(one(output_keys(), whole));
  out.push_back(one(dump_keys(), +[](const SimulationSpec& s) { return s.dump.enabled ? &s.dump : nullptr; }, true));
  out.push_back(one(poiseuille_keys(),
                    +[](const SimulationSpec& s) { return s.poiseuille.enabled ? &s.poiseuille : nullptr; }, true));
  out.push_back(one(rdf_keys(), +[](const SimulationSpec& s) { return s.rdf.enabled ? &s.rdf : nullptr; }, true));
  out.push_back(one(msd_keys(), +[](const SimulationSpec& s) { return s.msd.enabled ? &s.msd : nullptr; }, true));
  out.push_back(one(surface_tension_keys(),
                    +[](const SimulationSpec& s) { return s.surface_tension.enabled ? &s.surface_tension : nullptr; }, true));
  out.push_back(one(droplet_keys(), +[](const SimulationSpec& s) { return s.droplet.enabled ? &s.droplet : nullptr; }, true));
  out.push_back(one(stress_profile_keys(),
                    +[](const SimulationSpec& s) { return s.stress_profile.enabled ? &s.stress_profile : nullptr; }, true));
  {
    // [analysis.fields], or [[analysis.fields]] blocks named analysis.fields[k] when there are several.
    DeclaredTable t{fields_keys().path(), fields_keys().docs()};
    t.values = [](const SimulationSpec& spec) {
      Values out;
      for (std::size_t k = 0; k < spec.fields.size(); ++k)
        out.emplace_back(spec.fields.size() > 1 ? "analysis.fields[" + std::to_string(k) + "]" : "analysis.fields",
                         fields_keys().set_values(spec.fields[k]));
      return out;
    };
    out.push_back(std::move(t));
  }
  {
    // A [[solid]] block holds its own keys and its shape's.
    DeclaredTable t{solid_keys().path(), solid_keys().docs(), true,
                    "name = \"w\"\nspecies = \"A\"\nshape = \"union\""};
    for (keys::KeyDoc& row : shape_keys().docs()) t.rows.push_back(std::move(row));
    t.values = [](const SimulationSpec& spec) {
      Values out;
      for (std::size_t k = 0; k < spec.solids.size(); ++k) {
        std::vector<std::string> set = solid_keys().set_values(spec.solids[k]);
        const ShapeSpec& shape = spec.solids[k].shape;
        // The shape is always named: its default (a plane) is no default of a solid.
        std::vector<std::string> of_shape = shape_keys().set_values(shape);
        if (shape.kind == ShapeSpec{}.kind) of_shape.insert(of_shape.begin(), "shape = \"plane\"");
        set.insert(set.end(), of_shape.begin(), of_shape.end());
        out.emplace_back("solid[" + std::to_string(k) + "]", std::move(set));
      }
      return out;
    };
    out.push_back(std::move(t));
  }
  out.push_back(one(walls_keys(), +[](const SimulationSpec& s) { return s.solids.empty() ? nullptr : &s.walls; }));
  // The models that declare their own sections (engine/installer.hpp), in the list's order.
  for (const Model& m : models())
    if (m.section) {
      ModelSection section = m.section();
      DeclaredTable t{section.path, section.docs, static_cast<bool>(section.gather), section.minimal};
      t.values = [section](const SimulationSpec& spec) {
        Values out;
        if (const auto it = spec.models.find(section.path); it != spec.models.end())
          out.emplace_back(section.path, section.values(it->second));
        return out;
      };
      out.push_back(std::move(t));
    }
  return out;
}

std::string declared_tables_markdown() {
  std::string out;
  for (const DeclaredTable& t : declared_tables()) out += "<!-- keys: " + t.path + " -->\n" + keys::markdown(t.rows) + "\n";
  return out;
}

std::string model_numbers_summary(const SimulationSpec& spec) {
  std::string out;
  for (const Model& m : models())
    if (m.numbers) out += m.numbers(spec);
  return out;
}

std::string declared_values_summary(const SimulationSpec& spec) {
  std::string out;
  for (const DeclaredTable& t : declared_tables()) {
    if (!t.values) continue;
    for (const auto& [name, set] : t.values(spec)) {
      std::string line = "  " + name + ":";
      for (std::size_t k = 0; k < set.size(); ++k) line += (k ? ", " : " ") + set[k];
      if (set.empty()) line += " defaults";
      out += line + "\n";
    }
  }
  return out.empty() ? out : "settings (other than the defaults):\n" + out;
}

}  // namespace mesodpd
