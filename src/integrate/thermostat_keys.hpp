// [thermostat]: a pairwise thermostat after a conservative velocity-Verlet step
// (integrate/pair_thermostat.hpp). Its values, its declared keys and the cross-checks that the ranges cannot
// say; the section is a model's own (include/mesodpd/model_section.hpp), listed in engine/installers.cpp.
#pragma once
#include <optional>

#include "integrate/pair_thermostat.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

struct ThermostatSpec {
  PairThermostatKind type = PairThermostatKind::LoweAndersen;
  std::optional<double> rate;   // Gamma: Lowe-Andersen and Stoyanov-Groot only, required there
  std::optional<double> gamma;  // friction: Shardlow and Peters only, required there
  std::optional<double> alpha;  // Nose-Hoover coupling: Stoyanov-Groot only, required there
  double rc = 1.0;
  std::optional<double> s;  // weight exponent: Shardlow, Peters, Stoyanov-Groot (default 2)

  double exponent() const { return s.value_or(2.0); }
};

const keys::KeyTable<ThermostatSpec>& thermostat_keys();

// The checks of a [thermostat] against the rest of the spec; each refusal is a SpecError naming its key.
// Also run by the installer, for specs built in code that skip validate().
void check_thermostat(const ThermostatSpec& t, const SimulationSpec& spec);

// The sweep's parameters for a checked section.
PairThermostatParams thermostat_params(const ThermostatSpec& t, const SimulationSpec& spec);

// The model section the schema reads as [thermostat].
ModelSection thermostat_section();

}  // namespace mesodpd
