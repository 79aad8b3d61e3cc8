// A test-only analysis, written as the recipe of docs/architecture.md says a new analysis is: this file
// pair (its keys, section, stage, thermo column, checkpoint part, summary and installer) and its test
// (test_model_recipes.cpp); it joins through one register_model() call.
//
// [analysis.test_moments]: every `every` steps, the ratio <v^4> / <v^2>^2 over the mobile particles,
// which is 5/3 for a Maxwell-Boltzmann distribution in three dimensions whatever the temperature
// (<v^2k> = (2k+1)!! (kT/m)^k). Its running mean travels in checkpoints; the thermo column
// `v4_ratio` is the ratio at each thermo row.
#pragma once
#include <cstdint>

#include "engine/installer.hpp"

namespace mesodpd::test_models {

struct MomentsSpec {
  std::uint64_t every = 10;
};

// The ratio <v^4> / <v^2>^2 of the local particles of all ranks (collective; integer sums).
double v4_ratio(const StepContext& ctx);

Model moments_model();

}  // namespace mesodpd::test_models
