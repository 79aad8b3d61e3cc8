// The installer of [thermostat]: one AfterSecondHalf stage that runs the pair sweep of
// integrate/pair_thermostat.hpp on the step's complete velocities, before the health check and the
// analyses read them. The integrator's own step is Groot-Warren's with the pair law's gamma = 0, i.e.
// plain velocity Verlet for the conservative forces (lambda has no effect then).
#include <memory>
#include <string>

#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "integrate/thermostat_keys.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

void install_thermostat(Installation& in) {
  const ThermostatSpec* t = in.spec.model<ThermostatSpec>("thermostat");
  if (!t) return;
  check_thermostat(*t, in.spec);  // again, for specs built in code
  // A law with particle temperatures (eDPD) conserves energy with its own friction and heat: a sweep that
  // changes the kinetic energy behind its back would break that.
  if (pair_law(in.spec.pair_style).style == "edpd")
    throw SpecError("pair.style", "\"" + std::string(pair_law(in.spec.pair_style).style) + "\"",
                    "[thermostat] is not supported with a law that carries particle temperatures (its energy "
                    "balance has no place for the thermostat's heat)");
  if (in.sim.halo().comm().distributed())
    throw SpecError("thermostat.type", "",
                    "runs on one MPI rank only (the sweep is serial over all pairs); this run has " +
                        std::to_string(in.sim.halo().comm().size()) + " ranks");
  auto sweep = std::make_shared<PairThermostat>(thermostat_params(*t, in.spec));
  in.components.add(sweep);
  in.stages.add(StagePoint::AfterSecondHalf, make_stage([sweep](StepContext& ctx) {
                  sweep->sweep(ctx.particles, ctx.box, ctx.species_mass, ctx.step, ctx.dt);
                }));
}

}  // namespace mesodpd
