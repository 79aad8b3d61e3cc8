// BlowUpError: the run cannot go on because its state left what the engine can integrate (exit code 3
// of the mesodpd command). Its own header so that the initial-state checks can raise it too.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

namespace mesodpd {

// A run that went unstable: NaN, a particle faster than run.max_velocity, a bond past its maximum
// length (also in the initial state), a particle lost from a bounded axis.
class BlowUpError : public std::runtime_error {
 public:
  BlowUpError(std::uint64_t step, std::uint32_t id, const std::string& what)
      : std::runtime_error(what), step_(step), id_(id) {}
  std::uint64_t step() const { return step_; }
  std::uint32_t particle_id() const { return id_; }

 private:
  std::uint64_t step_;
  std::uint32_t id_;
};

}  // namespace mesodpd
