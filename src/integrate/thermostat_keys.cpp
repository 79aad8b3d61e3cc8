// The keys of [thermostat] and the checks of a section against the rest of the spec.
#include "integrate/thermostat_keys.hpp"

#include <algorithm>
#include <string>

namespace mesodpd {

namespace {

const char* type_word(PairThermostatKind k) {
  return k == PairThermostatKind::LoweAndersen ? "lowe-andersen"
         : k == PairThermostatKind::Shardlow   ? "shardlow"
         : k == PairThermostatKind::Peters     ? "peters"
                                               : "stoyanov-groot";
}

// The smallest reduced mass m_i m_j / (m_i + m_j) of any pair of particles: half the lightest mass.
double smallest_reduced_mass(const SimulationSpec& spec) {
  double m = spec.species.empty() ? 1.0 : spec.species.front().mass;
  for (const SpeciesSpec& s : spec.species) m = std::min(m, s.mass);
  return 0.5 * m;
}

}  // namespace

const keys::KeyTable<ThermostatSpec>& thermostat_keys() {
  using T = ThermostatSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("thermostat");
    t.choice("type", &T::type,
             {{"lowe-andersen", PairThermostatKind::LoweAndersen},
              {"shardlow", PairThermostatKind::Shardlow},
              {"peters", PairThermostatKind::Peters},
              {"stoyanov-groot", PairThermostatKind::StoyanovGroot}},
             "A pairwise thermostat applied after each conservative velocity-Verlet step, instead of the "
             "pair law's dissipative and random forces (which must be off: `pair.gamma = 0`). "
             "`lowe-andersen`: each pair within `rc` is re-thermalised along its line of centres with "
             "probability `rate` x dt (Lowe 1999). `shardlow`: Shardlow's S1 splitting of the DPD friction "
             "and noise, pair by pair. `peters`: Peters' (2004) pair update that keeps the pair's Maxwell "
             "distribution at any dt. `stoyanov-groot`: each pair gets a Lowe-Andersen collision with "
             "probability `rate` x dt, else a pairwise Nose-Hoover kick of strength `alpha` driven by the "
             "measured kinetic temperature (Stoyanov & Groot 2005). Under MPI the particles are gathered "
             "on rank 0 for the sweep (bit-identical to one rank; O(N) traffic per step). No `[[solid]]` walls "
             "or frozen species; not with `integrator.type = \"euler\"` or `pair.style = \"edpd\"`. Formulas: docs/physics.md; "
             "temperature against dt: docs/validation.md.");
    t.number("rate", &T::rate, keys::kNonNegative,
             "Lowe-Andersen and Stoyanov-Groot: collision rate Gamma per pair and unit time; rate x "
             "`integrator.dt` (the probability per step, P in Stoyanov & Groot) must be at most 1. Must be "
             "positive for lowe-andersen; 0 is allowed for stoyanov-groot (the Nose-Hoover part alone). "
             "Refused with the other types.")
        .default_text("required (lowe-andersen, stoyanov-groot)");
    t.number("gamma", &T::gamma, keys::kPositive,
             "Shardlow and Peters only: friction gamma of the dissipative force; the noise follows from "
             "sigma^2 = 2 gamma kT (seed 000 Eq. 7). Peters needs gamma x dt / mu <= 1 for the lightest "
             "pair (mu = m/2). Refused with lowe-andersen.")
        .default_text("required (shardlow, peters)");
    t.number("alpha", &T::alpha, keys::kPositive,
             "Stoyanov-Groot only: coupling alpha of the pairwise Nose-Hoover force alpha w_D (kT / T_kin - 1) "
             "(e . v_ij) e (a friction, mass per time); alpha x `integrator.dt` / mu must be at most 1 for "
             "the lightest pair (mu = m/2). Refused with the other types.")
        .default_text("required (stoyanov-groot)");
    t.number("rc", &T::rc, keys::kCutoff,
             "Cutoff of the thermostat's pairs; every periodic box length must be at least 2 rc.");
    t.number("s", &T::s, {0.0, 10.0, false, true},
             "Shardlow, Peters and Stoyanov-Groot: weight exponent, w_D = w_R^2 = (1 - r/rc)^s as the pair "
             "law's `s` (seed 000 Eq. 8). Refused with lowe-andersen.")
        .default_text("2.0");
    return t;
  }();
  return table;
}

void check_thermostat(const ThermostatSpec& t, const SimulationSpec& spec) {
  const std::string type = std::string("thermostat.type = \"") + type_word(t.type) + "\"";
  const bool la = t.type == PairThermostatKind::LoweAndersen;
  const bool sg = t.type == PairThermostatKind::StoyanovGroot;
  const bool friction = !la && !sg;  // shardlow, peters
  const std::string reads =
      " (lowe-andersen reads rate; shardlow and peters read gamma and s; stoyanov-groot reads rate, alpha "
      "and s)";
  if (!friction && t.gamma) keys::fail("thermostat.gamma", keys::show(*t.gamma), "not used by " + type + reads);
  if (la && t.s) keys::fail("thermostat.s", keys::show(*t.s), "not used by " + type + reads);
  if (friction && t.rate) keys::fail("thermostat.rate", keys::show(*t.rate), "not used by " + type + reads);
  if (!sg && t.alpha) keys::fail("thermostat.alpha", keys::show(*t.alpha), "not used by " + type + reads);
  if (!friction && !t.rate)
    keys::fail("thermostat.rate", "", "missing: " + type + " needs the collision rate Gamma");
  if (la && *t.rate == 0.0)
    keys::fail("thermostat.rate", "0", "must be positive for " + type + " (it is its only coupling)");
  if (friction && !t.gamma) keys::fail("thermostat.gamma", "", "missing: " + type + " needs the friction gamma");
  if (sg && !t.alpha)
    keys::fail("thermostat.alpha", "", "missing: " + type + " needs the Nose-Hoover coupling alpha");
  if (!friction && *t.rate * spec.dt > 1.0)
    keys::fail("thermostat.rate", keys::show(*t.rate),
               "rate x integrator.dt = " + keys::show(*t.rate * spec.dt) +
                   " must be at most 1 (it is the probability of a collision per pair and step)");
  // Peters' friction and Stoyanov-Groot's Nose-Hoover kick move u by (coupling) dt / mu of itself: more
  // than 1 would turn a pair's relative velocity past zero.
  const auto at_most_one = [&](const char* key, double coupling) {
    const double mu = smallest_reduced_mass(spec);
    if (coupling * spec.dt / mu > 1.0)
      keys::fail(std::string("thermostat.") + key, keys::show(coupling),
                 std::string(key) + " x integrator.dt / mu = " + keys::show(coupling * spec.dt / mu) +
                     " (mu = " + keys::show(mu) + ", half the lightest mass) must be at most 1 for " + type);
  };
  if (t.type == PairThermostatKind::Peters) at_most_one("gamma", *t.gamma);
  if (sg) at_most_one("alpha", *t.alpha);
  for (int d = 0; d < 3; ++d)
    if (spec.periodic[static_cast<std::size_t>(d)] && spec.box[static_cast<std::size_t>(d)] < 2.0 * t.rc)
      keys::fail("thermostat.rc", keys::show(t.rc), "every periodic box length must be at least 2 rc");
  // The thermostat supplies all the dissipation and noise: the pair law's must be off.
  for (std::size_t k = 0; k < spec.pair_section.overrides.size(); ++k)
    if (const auto& g = spec.pair_section.overrides[k].params.gamma; g && *g != 0.0)
      keys::fail("pair.override[" + std::to_string(k) + "].gamma", keys::show(*g),
                 "must be 0 with [thermostat]: the thermostat supplies the dissipative and random forces");
  for (const PairSpec& p : spec.pairs)
    if (p.gamma != 0.0)
      keys::fail("pair.gamma", keys::show(p.gamma),
                 "must be 0 with [thermostat] (the default is 4.5): the thermostat supplies the dissipative "
                 "and random forces");
  if (spec.integrator != IntegratorKind::GrootWarren)
    keys::fail("integrator.type", "\"euler\"",
               "[thermostat] follows a velocity-Verlet step: use integrator.type = \"groot-warren\"");
  for (std::size_t k = 0; k < spec.species.size(); ++k)
    if (spec.species[k].frozen)
      keys::fail("species[" + std::to_string(k) + "].frozen", "true",
                 "frozen species (walls) are not supported with [thermostat]");
  if (!spec.solids.empty()) keys::fail("solid", "", "[[solid]] walls are not supported with [thermostat]");
}

PairThermostatParams thermostat_params(const ThermostatSpec& t, const SimulationSpec& spec) {
  PairThermostatParams p;
  p.kind = t.type;
  p.rate = t.rate.value_or(0.0);
  p.gamma = t.gamma.value_or(0.0);
  p.alpha = t.alpha.value_or(0.0);
  p.rc = t.rc;
  p.s = t.exponent();
  p.kT = spec.kT;
  p.seed = spec.seed;
  return p;
}

ModelSection thermostat_section() { return model_section(thermostat_keys(), check_thermostat); }

}  // namespace mesodpd
