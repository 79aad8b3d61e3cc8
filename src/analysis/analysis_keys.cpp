// The keys of [analysis.rdf], [analysis.msd], [analysis.surface_tension], [analysis.droplet] and
// [analysis.stress_profile]; cross-checks against the box and other sections are in src/schema/validate.cpp.
#include "analysis/analysis_keys.hpp"

namespace mesodpd {

const keys::KeyTable<RdfSpec>& rdf_keys() {
  using T = RdfSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("analysis.rdf");
    t.integer("bins", &T::bins, {1}, "Histogram bins of g(r).");
    t.number("rmax", &T::rmax, keys::kPositive, "Largest distance sampled.")
      .allowed("> 0 and < half the smallest box length");
    t.integer("start", &T::start, {0}, "First sampled step.");
    t.integer("every", &T::every, {1}, "Sampling interval.");
    return t;
  }();
  return table;
}

const keys::KeyTable<MsdSpec>& msd_keys() {
  using T = MsdSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("analysis.msd");
    t.integer("start", &T::start, {0}, "Step taken as the time origin.");
    t.integer("every", &T::every, {1}, "Sampling interval.");
    return t;
  }();
  return table;
}

const keys::KeyTable<SurfaceTensionSpec>& surface_tension_keys() {
  using T = SurfaceTensionSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("analysis.surface_tension");
    t.axis("axis", &T::axis, "Normal of the interfaces.");
    t.integer("start", &T::start, {0}, "First thermo row used (equilibration before it).");
    t.integer("blocks", &T::blocks, {2, 1000}, "Blocks of the error bar.");
    return t;
  }();
  return table;
}

const keys::KeyTable<DropletSpec>& droplet_keys() {
  using T = DropletSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("analysis.droplet");
    t.integer("start", &T::start, {0}, "First sampled step (equilibration before it).");
    t.integer("every", &T::every, {1}, "Sampling interval.");
    t.number("inner_radius", &T::inner_radius, keys::kPositive, "Radius of the liquid core where P_in and ρ_in are measured.")
      .default_text("required");
    t.number("outer_radius", &T::outer_radius, keys::kPositive, "The vapour region is the box outside this sphere.")
      .default_text("required")
      .allowed("> `inner_radius`, < half the smallest box length");
    t.number("bin_width", &T::bin_width, keys::kPositive, "Bins of the radial profile.")
      .allowed("> 0, < half the smallest box length");
    t.integer("blocks", &T::blocks, {2, 1000}, "Blocks of the error bars.");
    return t;
  }();
  return table;
}

const keys::KeyTable<StressProfileSpec>& stress_profile_keys() {
  using T = StressProfileSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("analysis.stress_profile");
    t.axis("axis", &T::axis, "Normal of the slabs (of the membrane).")
      .allowed("`\"x\"`, `\"y\"`, `\"z\"`; periodic");
    t.integer("bins", &T::bins, {1, 100000}, "Slabs across the box.");
    t.integer("start", &T::start, {0}, "First sampled step (equilibration before it).");
    t.integer("every", &T::every, {1}, "Sampling interval.");
    t.integer("blocks", &T::blocks, {2, 1000}, "Blocks of the error bars.");
    t.choice("assignment", &T::assignment, {{"contour", StressAssignment::Contour}, {"half", StressAssignment::Half}}, "How a pair's virial is shared between slabs (above).");
    return t;
  }();
  return table;
}

}  // namespace mesodpd
