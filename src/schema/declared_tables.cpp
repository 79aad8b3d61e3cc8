// The list of declared key tables (one entry per model section), for the docs and their test.
#include "schema/declared_tables.hpp"

#include "analysis/analysis_keys.hpp"
#include "boundary/boundary_keys.hpp"
#include "engine/bonded_keys.hpp"
#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/run_keys.hpp"
#include "integrate/integrator_keys.hpp"

namespace mesodpd {

std::vector<DeclaredTable> declared_tables() {
  std::vector<DeclaredTable> out;
  const auto add = [&](const auto& table) { out.push_back({table.path(), table.docs(), false, {}}); };
  add(system_keys());
  out.push_back({"pair", pair_key_docs()});
  out.push_back({"pair.override", pair_override_key_docs(), true, "species = [\"A\", \"A\"]"});
  add(integrator_keys());
  add(run_keys());
  add(neighbor_keys());
  add(parallel_keys());
  add(bonds_keys());
  add(init_keys());
  add(output_keys());
  add(dump_keys());
  add(poiseuille_keys());
  add(rdf_keys());
  add(msd_keys());
  add(surface_tension_keys());
  add(droplet_keys());
  add(stress_profile_keys());
  add(walls_keys());
  // The models that declare their own sections (engine/installer.hpp), in the list's order.
  for (const Model& m : models())
    if (m.section) {
      const ModelSection section = m.section();
      out.push_back({section.path, section.docs, false, section.minimal});
    }
  return out;
}

std::string declared_tables_markdown() {
  std::string out;
  for (const DeclaredTable& t : declared_tables()) out += "<!-- keys: " + t.path + " -->\n" + keys::markdown(t.rows) + "\n";
  return out;
}

}  // namespace mesodpd
