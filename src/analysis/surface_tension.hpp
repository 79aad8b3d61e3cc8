// The surface tension of planar interfaces normal to one axis from the pressure tensor (Kirkwood-Buff
// mechanical route): a periodic box holding a slab has two interfaces, so
//   sigma = (L_n / 2) < P_nn - (P_t1 t1 + P_t2 t2) / 2 >
// with n the normal axis and L_n the box length along it; the mean over thermo rows carries a block
// error bar (issue 11 item 3). A homogeneous fluid gives sigma = 0 within the error.
#pragma once
#include "analysis/analysis_stage.hpp"
#include "mesodpd/spec.hpp"
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "io/byte_buffer.hpp"

namespace mesodpd {

// Mean of a time series and its standard error from `blocks` contiguous blocks of equal length (samples
// beyond blocks * floor(n / blocks) at the start are dropped, the end being the equilibrated part).
// err is NaN with fewer than two blocks of at least one sample.
struct BlockMean {
  double mean = 0, err = 0;
  std::size_t samples = 0;   // samples used
  std::size_t blocks = 0;    // blocks behind err
};
BlockMean block_mean(const std::vector<double>& x, std::size_t blocks);

// P_nn - (P_t1 t1 + P_t2 t2) / 2 of a pressure tensor stored xx yy zz xy xz yz, for normal axis n.
double normal_minus_tangential(const std::array<double, 6>& p, int normal_axis);

class SurfaceTension {
 public:
  // normal_axis 0, 1, 2; length = the box length along it; blocks >= 2.
  SurfaceTension(int normal_axis, double length, std::size_t blocks);

  void add(const std::array<double, 6>& pressure_tensor) {
    anisotropy_.push_back(normal_minus_tangential(pressure_tensor, axis_));
  }
  // sigma and its error bar in k_BT / r_c^2 (two interfaces: factor L_n / 2).
  BlockMean result() const;
  std::size_t samples() const { return anisotropy_.size(); }
  // surface_tension.json: sigma, sigma_err, samples, blocks, axis, length.
  void write_json(const std::string& path) const;

  void save(ByteWriter& w) const { w.put_vector(anisotropy_); }
  void load(ByteReader& r, const std::string&) { anisotropy_ = r.get_vector<double>(); }

 private:
  int axis_;
  double length_;
  std::size_t blocks_;
  std::vector<double> anisotropy_;  // one per thermo row sampled
};

class Comm;
class ThermoOutput;

// [analysis.surface_tension] as an EndOfStep stage after the thermo rows: adds the pressure tensor of
// each thermo row from surface_tension.start on (on the root); surface_tension.json and sigma at the end.
class SurfaceTensionStage final : public RootAnalysisStage<SurfaceTension> {
 public:
  SurfaceTensionStage(const SurfaceTensionSpec& spec, AnalysisOutput out, const ThermoOutput& thermo,
                      double normal_length, const Comm& comm);
  void observe(const StepContext& ctx) override;
  std::string finish(const StepContext& ctx) override;

 private:
  const SurfaceTensionSpec& spec_;
  const ThermoOutput& thermo_;
};

}  // namespace mesodpd
