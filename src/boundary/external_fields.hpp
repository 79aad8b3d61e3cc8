// External force fields as Forces stages: a constant body force per species and the reverse-Poiseuille
// driving field. They run after the pair forces, in the order registered.
#pragma once
#include <array>
#include <vector>

#include "core/stage.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

// [[species]] body_force: a constant force on every particle of a species.
class SpeciesBodyForce final : public Stage {
 public:
  explicit SpeciesBodyForce(std::vector<std::array<double, 3>> force_by_species)
      : force_(std::move(force_by_species)) {}
  void run(StepContext& ctx) override;

 private:
  std::vector<std::array<double, 3>> force_;
};

// [poiseuille]: reverse Poiseuille flow (Backer et al., seed 002): an acceleration +g along the flow
// axis where the gradient coordinate lies in the lower half of the box, -g in the upper half.
class ReversePoiseuilleField final : public Stage {
 public:
  ReversePoiseuilleField(double g, int flow_axis, int gradient_axis)
      : g_(g), flow_axis_(flow_axis), gradient_axis_(gradient_axis) {}
  void run(StepContext& ctx) override;

 private:
  double g_;
  int flow_axis_, gradient_axis_;
};

// Registers the fields the spec asks for at StagePoint::Forces: body forces, then reverse Poiseuille.
void add_external_fields(const SimulationSpec& spec, StageList& stages);

}  // namespace mesodpd
