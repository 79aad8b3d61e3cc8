// The installer of [[solid]] walls: the walls' stages (boundary/walls.hpp), their drag analysis and
// adaptive-force log (analysis/wall_drag.hpp), their thermo columns and their checkpoint section.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "analysis/thermo.hpp"
#include "analysis/wall_drag.hpp"
#include "boundary/walls.hpp"
#include "engine/installer.hpp"
#include "engine/simulation.hpp"
#include "io/byte_buffer.hpp"

namespace mesodpd {

void install_walls(Installation& in) {
  const SimulationSpec& spec = in.spec;
  if (spec.solids.empty()) return;
  Simulation& sim = in.sim;
  const Comm& comm = sim.halo().comm();
  // Penetrations mirrored right after the positions move, reflections in the layer after the velocities
  // are complete, drag samples at the end of each step, the reflection and penetration counts as thermo
  // columns, and the drag averages (and adaptive force) in checkpoints.
  // Solids that a model moves (rigid bodies) are left to it.
  const ReleasedSolids* released = in.components.find<ReleasedSolids>();
  Walls& w = in.components.add(std::make_shared<Walls>(spec, sim.box(), spec.integrator == IntegratorKind::GrootWarren,
                                                       released ? released->released : std::vector<std::uint8_t>{}));
  in.stages.add(StagePoint::AfterFirstHalf, make_stage([&w](StepContext& ctx) { w.mirror_positions(ctx); }));
  in.stages.add(StagePoint::AfterSecondHalf, make_stage([&w](StepContext& ctx) { w.reflect_velocities(ctx); }));
  WallDrag& drag = in.components.share(in.stages.add(
      StagePoint::EndOfStep, std::make_unique<WallDrag>(spec, w, in.options.out_dir, in.restarted, comm)));
  if (w.adaptive()) {
    // The adaptive near-wall force: applied with the other external forces, adjusted after the drag
    // sample (the drag takes the force of this step's evaluation back from the solids).
    in.stages.add(StagePoint::Forces, make_stage([&w](StepContext& ctx) { w.add_adaptive_force(ctx); }));
    in.stages.add(StagePoint::EndOfStep, make_stage([&w](StepContext& ctx) { w.adapt(ctx); }));
    in.stages.add(StagePoint::EndOfStep,
                  std::make_unique<AdaptiveLog>(spec, w, in.options.out_dir, in.restarted, comm));
  }
  in.sections.push_back({"walls",
                         [&w, &drag](ByteWriter& out) {
                           drag.save(out);
                           w.save(out);
                         },
                         [&w, &drag](ByteReader& r, const std::string& context) {
                           drag.load(r, context);
                           w.load(r, context);
                         }});
  in.summaries.push_back([&drag](const StepContext& ctx) {
    const std::string text = drag.finish(ctx.comm);
    return ctx.comm.root() ? text : std::string();
  });
  if (!in.restarted) {
    // The initial velocities obey the wall rule like every end-of-step one (a fast particle next to a
    // surface would otherwise cross it in the first move); the ghosts and forces then belong to them.
    // The new velocities change the dissipative forces, hence the predicted first move (by up to ~1e-3
    // in examples/porous, enough to end a move a hair inside a solid): passes repeat until one changes
    // no velocity (each shrinks the changes ~10-fold). Runs that need no second pass are unchanged.
    for (int pass = 0; pass < 20; ++pass) {
      StepContext ctx = in.context();
      w.reflect_velocities(ctx);
      if (pass > 0 && w.last_changes(comm) == 0) break;
      in.refresh();
    }
  }
  auto counts = std::make_shared<std::array<std::uint64_t, 2>>();
  in.thermo_columns.push_back({"reflections", [&w, counts](const StepContext& ctx) {
                                 *counts = w.take_counts(ctx.comm);
                                 return static_cast<double>((*counts)[0]);
                               }});
  in.thermo_columns.push_back(
      {"penetrations", [counts](const StepContext&) { return static_cast<double>((*counts)[1]); }});
  // Flows between walls stream: the temperature of the velocities relative to the mean velocity of bins
  // about one cutoff wide is the heat (thermo's own temperature counts the flow too). At most ~65,536
  // bins (wider bins in large boxes), so that a thermo row's integer sums stay small.
  const Box& box = sim.box();
  const double bin_width = std::max(sim.pair_backend().max_cutoff(), std::cbrt(box.volume() / 65536.0));
  std::array<int, 3> bins{};
  for (int d = 0; d < 3; ++d)
    bins[static_cast<std::size_t>(d)] = std::max(1, static_cast<int>(box.length(d) / bin_width));
  std::vector<std::uint8_t> frozen;
  for (const auto& s : spec.species) frozen.push_back(s.frozen ? 1 : 0);
  in.temperature_column = static_cast<int>(in.thermo_columns.size());
  in.thermo_columns.push_back({"temperature_peculiar", [bins, frozen](const StepContext& ctx) {
                                 return peculiar_temperature(ctx.particles, ctx.species_mass, ctx.box, bins, ctx.comm,
                                                             frozen);
                               }});
}

}  // namespace mesodpd
