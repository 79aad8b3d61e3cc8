// The [lees_edwards] block (engine/install_lees_edwards.cpp has its keys and stages). In a header of its
// own so that other models can read the shear a run imposes (spec.model<LeesEdwardsSpec>("lees_edwards")):
// the rigid bodies start a new run moving with the imposed profile, as the fluid does.
#pragma once
#include <cmath>
#include <cstdint>
#include <optional>

#include "mesodpd/spec.hpp"

namespace mesodpd {

struct LeesEdwardsSpec {
  int flow = 0, gradient = 1;
  std::optional<double> shear_rate;
  std::optional<double> strain_amplitude, omega;
  bool initial_profile = true;
  std::uint64_t stress_every = 10;
  std::uint64_t equilibrate = 0;
  int blocks = 10;

  bool oscillatory() const { return omega.has_value(); }
  // The shear rate at t = 0 (the steady rate, or gamma_0 omega).
  double initial_rate() const { return oscillatory() ? *strain_amplitude * *omega : *shear_rate; }
  // The largest image velocity |dU| = |rate| L_g over the run.
  double max_image_velocity(const SimulationSpec& spec) const {
    return std::abs(initial_rate()) * spec.box[static_cast<std::size_t>(gradient)];
  }
};

}  // namespace mesodpd
