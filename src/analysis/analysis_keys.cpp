// The keys of [analysis.rdf], [analysis.msd], [analysis.fields], [analysis.surface_tension],
// [analysis.droplet] and [analysis.stress_profile]; cross-checks against the box and other sections are in src/schema/validate.cpp.
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

const keys::KeyTable<FieldsSpec>& fields_keys() {
  using T = FieldsSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("analysis.fields");
    t.string("name", &T::name, "Prefix of the output files.")
      .allowed("letters, digits, `_`, `-`; unique per run");
    t.ints3("bins", &T::bins, {1}, "bins", "Bins along x, y, z; 1 averages over that axis.")
      .allowed("each >= 1, at most 4,000,000 bins in all");
    t.vec3("lo", &T::lo, keys::kFinite, "Lower corner of the binned region.")
      .default_text("[0.0, 0.0, 0.0]")
      .allowed("`0 <= lo < box`");
    t.vec3("hi", &T::hi, keys::kFinite, "Upper corner. Particles outside `[lo, hi)` are not binned.")
      .default_text("the box lengths")
      .allowed("`lo < hi <= box`");
    t.integer("start", &T::start, {0}, "First sampled step.");
    t.integer("every", &T::every, {1}, "Sampling interval (steps that are multiples of it, from `start`).");
    t.strings("species", &T::species, "Species whose particles make `density`, `velocity` and `temperature`.")
      .default_text("all species")
      .allowed("species names");
    t.strings("exclude", &T::exclude, "Or: every species but these (e.g. frozen wall particles).")
      .default_text("none")
      .allowed("species names; not with `species`");
    t.choice("centre", &T::centre_axis, {{"none", -1}, {"x", 0}, {"y", 1}, {"z", 2}}, "Shift each sample along this axis so that the selected species' centre of mass sits at the middle of the box: a slab or drop that drifts does not smear the profile.")
      .allowed("`\"none\"`, `\"x\"`, `\"y\"`, `\"z\"` (a periodic axis)");
    t.choice("fit", &T::fit, {{"none", FieldsFit::None}, {"slab", FieldsFit::Slab}}, "`\"slab\"`: fit a tanh profile to the 1-D density (needs `bins` > 1 along exactly one axis, and at least 8 there).");
    t.integer("blocks", &T::blocks, {2}, "Blocks for the slab fit's error bars: samples go into B to 2B − 1 blocks of equal size (merged pairwise as the run grows); each block's profile is fitted on its own.");
    t.strings("means", &T::means, "Per-particle fields averaged over the selected species' particles in each bin, written as `mean_<field>` (VTK array, CSV column, JSON): `[\"temp\"]` bins eDPD's internal temperature (`pair.style = \"edpd\"`). A field the run does not hold is an error at the first sample, naming this key.")
      .default_text("none")
      .allowed("names of floating-point particle fields (`temp`, `temp_rate`, `fx`, ...)");
    t.integer("write_every", &T::write_every, {0}, "Also write the output files at the steps that are multiples of this (after `start`; the averages go on, and the end of the run writes them again), to look at a long run while it goes; 0: at the end only.");
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
