// The keys of [[species]]. The reader adds what depends on other tables (a frozen species, a data file,
// density or count; src/schema/config.cpp) and validate() the names and the geometric mixing.
#include "schema/species_keys.hpp"

namespace mesodpd {

const keys::KeyTable<SpeciesSpec>& species_keys() {
  using T = SpeciesSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("species");
    t.string("name", &T::name, "Name used in `[[pair.override]]` and output.")
      .required()
      .allowed("non-empty, letters/digits/`_`, unique");
    t.number("mass", &T::mass, keys::kPositive, "Particle mass.");
    t.number("a", &T::a, keys::kNonNegative, "Self repulsion a_i, used only by `pair.mixing = \"geometric\"` (then required for every species; an error otherwise).");
    t.vec3("body_force", &T::body_force, keys::kFinite, "Constant external force on every particle of this species (e.g. gravity-driven flow).");
    t.number("density", &T::density, keys::kPositive, "Number density; the count is round(density x box volume). The total over all species may not exceed 4,294,967,295 (32-bit particle ids).")
      .default_text("—");
    t.integer("count", &T::count, {}, "Number of particles.")
      .default_text("—")
      .allowed(">= 0");
    t.choice("placement", &T::placement, {{"random", Placement::Random}, {"lattice", Placement::Lattice}}, "How generated particles are placed: uniformly at random, or on a regular lattice.");
    t.boolean("frozen", &T::frozen, "Wall particles: never integrated (infinite mass, they keep their wall's velocity), left out of the temperature and kinetic sums of `thermo.csv`, and pairs of two frozen particles are skipped by the pair loop. A frozen species has no `density`, `count`, `placement` or `body_force`: its particles are the fluid frozen inside `[[solid]]` blocks. Its pair parameters with the fluid species (`[[pair.override]]`) set the wall-fluid interaction.");
    t.custom("region", "shape table", "none (the whole box)", "a shape of [`[[solid]]`](#solid-optional-repeatable) (`shape` and its keys), as an inline table; not for a frozen species nor with `init.lammps_data`", "Place this species only inside the region: the species is generated over the whole box as usual (`density` and `count` are of the box), and a particle is kept if it falls inside the region (signed distance < 0) or inside a `[[solid]]`, where it becomes a wall particle as always; the others are not created (ids stay consecutive). So `[[solid]]` walls are the same with or without a region, and a liquid can start as a drop or a slab: `region = {shape = \"cylinder\", center = [16, 0, 5.6], direction = [0, 1, 0], radius = 4}` (`examples/wetting/`). Shape keys are checked as a solid's (errors name `species[k].region.radius` etc.), without the thickness rule. Molecules are not restricted by it. The densities that `mesodpd check` and the wall drag (C_D) derive from the spec count the box's draws, not the particles kept.");
    return t;
  }();
  return table;
}

}  // namespace mesodpd
