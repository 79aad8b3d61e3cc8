// The keys of [integrator]: the scheme, the time step and the velocity-prediction factor.
#include "integrate/integrator_keys.hpp"

namespace mesodpd {

const keys::KeyTable<SimulationSpec>& integrator_keys() {
  using S = SimulationSpec;
  static const keys::KeyTable<S> table = [] {
    keys::KeyTable<S> t("integrator");
    t.choice("type", &S::integrator, {{"groot-warren", IntegratorKind::GrootWarren}, {"euler", IntegratorKind::Euler}},
             "`groot-warren`: modified velocity-Verlet with a predicted velocity (seed 000 Eq. 10). `euler`: explicit "
             "Euler (seed 000 Eq. 9), for comparison only: its temperature drifts with dt.");
    t.number("dt", &S::dt, {0.0, 0.5, false, true},
             "Time step. 0.04 with lambda = 0.5 is the usual choice for rho = 3, sigma = 3 (seed 000 Sec. 2.5.2).")
      .unit("tau");
    t.number("lambda", &S::lambda, {0.0, 1.0, true, true},
             "Velocity-prediction factor of Eq. 10 (seed 000). Refused with `type = \"euler\"`.");
    return t;
  }();
  return table;
}

}  // namespace mesodpd
