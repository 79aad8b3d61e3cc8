// The keys of [[solid]] and its shape tables (also [[species]] region), [walls] (reflection, frozen depth,
// drag, adaptive force) and [poiseuille] (reverse Poiseuille flow); their cross-checks are in
// src/schema/validate.cpp.
#include "boundary/boundary_keys.hpp"

namespace mesodpd {

const keys::KeyTable<WallsSpec>& walls_keys() {
  using T = WallsSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("walls");
    t.choice("reflection", &T::reflection, {{"bounce_back", ReflectionKind::BounceBack}, {"specular", ReflectionKind::Specular}, {"maxwell", ReflectionKind::Maxwell}, {"none", ReflectionKind::None}}, "Velocity rule in the reflecting layer and for particles about to cross a surface: all components reversed relative to the wall (no slip), the normal component reversed (free slip), or redrawn from the Maxwell distribution at `system.kT` around the wall velocity, normal component (flux-weighted) pointing into the fluid. `\"none\"` only mirrors penetrating particles, leaving their velocity.");
    t.number("layer", &T::layer, {0, 1, true, true}, "Thickness of the reflecting layer (seed 000 Sect. 3.2.1); 0: reflect only particles whose next move would cross a surface.");
    t.integer("equilibrate", &T::equilibrate, {0}, "Steps of the whole box as one periodic fluid before the walls are frozen from it (above); 0: freeze the initial random placement.")
      .allowed(">= 0; not with `[[molecule]]`");
    t.number("depth", &T::depth, keys::kNonNegative, "Frozen shell kept inside every solid. Walls at bounded faces and solids with fluid on both sides (boxes, cylinders, spheres, pillars) must be at least this thick, or the run is refused: the fluid would interact through them.")
      .default_text("largest cutoff");
    t.integer("drag_start", &T::drag_start, {0}, "Steps before drag sampling starts.");
    t.integer("drag_every", &T::drag_every, {1}, "Drag sampling interval.");
    t.integer("drag_blocks", &T::drag_blocks, {2}, "Blocks of the drag error bar.");
    t.number("reference_area", &T::reference_area, keys::kNonNegative, "A of C_D = 2 F_D / (rho u^2 A) (seed 004 Eq. 10), with F_D the drag along the mean fluid velocity u and rho the fluid's fill mass density; for a pillar of diameter d across a channel of height h, A = d h.")
      .default_text("0 (none)");
    t.number("reference_length", &T::reference_length, keys::kNonNegative, "d of Re = rho u d / mu (seed 004 Eq. 11).")
      .default_text("0 (none)");
    t.number("viscosity", &T::viscosity, keys::kNonNegative, "mu of Re (measured separately, e.g. by reverse Poiseuille flow).")
      .default_text("0 (none)");
    t.boolean("adaptive", &T::adaptive, "Adaptive near-wall force (above).");
    t.integer("adaptive_bins", &T::adaptive_bins, {1, 1000}, "Bins per solid between `layer` and `adaptive_range`.");
    t.number("adaptive_range", &T::adaptive_range, keys::kNonNegative, "Reach of the adaptive force from each surface.")
      .default_text("largest cutoff")
      .allowed("> `layer`");
    t.number("adaptive_gain", &T::adaptive_gain, {0, 2, false, true}, "Potential step per update, in kT ln(rho_k / rho_bulk); 1 is the full correction for an ideal gas, a dense fluid responds less.");
    t.integer("adaptive_every", &T::adaptive_every, {1}, "Steps between updates (the densities are counted at every step).");
    t.integer("adaptive_stop", &T::adaptive_stop, {0}, "No updates after this step: the force stays as it is.")
      .default_text("0 (never)");
    return t;
  }();
  return table;
}

const keys::KeyTable<ShapeSpec>& shape_keys() {
  using T = ShapeSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("shape");
    t.choice("shape", &T::kind, {{"plane", ShapeKind::Plane}, {"cylinder", ShapeKind::Cylinder}, {"sphere", ShapeKind::Sphere}, {"box", ShapeKind::Box}, {"pillars", ShapeKind::Pillars}, {"image", ShapeKind::Image}, {"union", ShapeKind::Union}, {"difference", ShapeKind::Difference}}, "The shape (its signed distance: the table below) and the keys it reads; a key that the shape does not read is refused.")
      .required(" (plane, cylinder, sphere, box, pillars, image, union or difference)")
      .selects("not used by {key} = {value}", " (needed by {key} = {value})")
      .variant(ShapeKind::Plane, {"point", "normal"})
      .variant(ShapeKind::Cylinder, {"center", "direction", "radius"})
      .variant(ShapeKind::Sphere, {"center", "radius"})
      .variant(ShapeKind::Box, {"lo", "hi"})
      .variant(ShapeKind::Pillars, {"lattice", "spacing", "radius"}, {"axis", "point"})
      .variant(ShapeKind::Image, {"file", "voxel_size"}, {"axis", "invert"})
      .variant(ShapeKind::Union, {"parts"})
      .variant(ShapeKind::Difference, {"parts"});
    t.vec3("point", &T::point, keys::kFinite, "`plane`: a point of the surface; `pillars`: the lattice origin.")
      .default_text("required (plane); [0.0, 0.0, 0.0] (pillars)");
    t.vec3("normal", &T::normal, keys::kFinite, "`plane`: the normal, pointing into the fluid (normalised; not the zero vector, and along bounded axes only).");
    t.vec3("center", &T::center, keys::kFinite, "`cylinder`: a point of the axis; `sphere`: the centre.");
    t.vec3("direction", &T::direction, keys::kFinite, "`cylinder`: the direction of the axis (normalised; not the zero vector).");
    t.number("radius", &T::radius, keys::kPositive, "`cylinder`, `sphere`, `pillars`: the radius.")
      .allowed("> 0; 2 x radius >= `walls.depth`");
    t.vec3("lo", &T::lo, keys::kFinite, "`box`: the lower corner.");
    t.vec3("hi", &T::hi, keys::kFinite, "`box`: the upper corner.")
      .allowed("> `lo`; hi - lo >= `walls.depth` where the box ends inside the simulation box");
    t.choice("lattice", &T::lattice, {{"square", Lattice::Square}, {"hexagonal", Lattice::Hexagonal}}, "`pillars`: the lattice of the pillar axes.")
      .default_text("required (pillars)");
    t.number("spacing", &T::spacing, keys::kPositive, "`pillars`: the centre-to-centre distance L.")
      .allowed("> 2 x `radius`");
    t.axis("axis", &T::axis, "`pillars`: the pillar axis; `image`: the extrusion axis of a 2-D image.");
    t.string("file", &T::file, "`image`: a PGM (2-D, extruded) or MESODPD-VOXELS (3-D) file (*Image files* below); relative to the config file.")
      .default_text("required (image)")
      .allowed("an existing file");
    t.number("voxel_size", &T::voxel_size, keys::kPositive, "`image`: the edge of one pixel or voxel (the image covers the box exactly).");
    t.boolean("invert", &T::invert, "`image`: swap solid and fluid.");
    t.custom("parts", "array of shape tables", "required (union, difference)", "at least one shape", "`union`, `difference`: the shapes combined, inline tables with `shape` and its keys.");
    return t;
  }();
  return table;
}

const keys::KeyTable<SolidSpec>& solid_keys() {
  using T = SolidSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("solid");
    t.string("name", &T::name, "Body name (columns of `drag.csv`).")
      .required()
      .allowed("letters/digits/`_`, unique");
    t.string("species", &T::species, "The species its frozen particles become.")
      .required(" (the frozen species its particles become)")
      .allowed("a species with `frozen = true`");
    t.vec3("velocity", &T::velocity, keys::kFinite, "Wall velocity (Couette flow): the body's particles move with it, and reflections are taken relative to it.")
      .allowed("finite; only for planes, perpendicular to `normal`");
    return t;
  }();
  return table;
}

const keys::KeyTable<PoiseuilleSpec>& poiseuille_keys() {
  using T = PoiseuilleSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("poiseuille");
    t.number("force", &T::force, keys::kFinite, "Acceleration g (force per unit mass).")
      .required(" (the body acceleration g of reverse Poiseuille flow)")
      .allowed("finite, != 0");
    t.axis("flow_axis", &T::flow_axis, "Direction of the driving force.");
    t.axis("gradient_axis", &T::gradient_axis, "Direction across which the velocity varies.")
      .allowed("`\"x\"`, `\"y\"`, `\"z\"`, not `flow_axis`");
    t.integer("bins", &T::bins, {4}, "Velocity-profile bins along the gradient axis (even, so each half has whole bins).")
      .allowed(">= 4, even");
    t.integer("start", &T::start, {0}, "Steps before sampling begins (equilibration). It may exceed `run.steps`, since the command line can change the step count.");
    t.integer("every", &T::every, {1}, "Sampling interval.");
    t.integer("blocks", &T::blocks, {2}, "Number of blocks for the viscosity's block-average error bar.");
    return t;
  }();
  return table;
}

}  // namespace mesodpd
