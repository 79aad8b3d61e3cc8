// The keys of [walls] (reflection, frozen depth, drag, adaptive force) and [poiseuille] (reverse Poiseuille
// flow); their cross-checks are in src/schema/validate.cpp.
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
