// [analysis.test_moments] (velocity_moments.hpp).
#include "modules/velocity_moments.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <span>

#include "io/byte_buffer.hpp"
#include "mesodpd/model_section.hpp"
#include "parallel/comm.hpp"

namespace mesodpd::test_models {

namespace {

const keys::KeyTable<MomentsSpec>& moments_keys() {
  static const keys::KeyTable<MomentsSpec> table = [] {
    keys::KeyTable<MomentsSpec> t("analysis.test_moments");
    t.integer("every", &MomentsSpec::every, {1}, "Steps between samples.");
    return t;
  }();
  return table;
}

// The running mean of the ratio over samples.
class Moments final : public Stage {
 public:
  explicit Moments(std::uint64_t every) : every_(every) {}
  void run(StepContext& ctx) override {
    if (ctx.step % every_ != 0) return;
    sum_ += v4_ratio(ctx);
    ++samples_;
  }
  void save(ByteWriter& w) const {
    w.put<double>(sum_);
    w.put<std::uint64_t>(samples_);
  }
  void load(ByteReader& r) {
    sum_ = r.get<double>();
    samples_ = r.get<std::uint64_t>();
  }
  std::string summary() const {
    return fmt::format("velocity moments: <v^4>/<v^2>^2 = {:.5f} over {} samples (Maxwell-Boltzmann: 5/3)\n",
                       samples_ ? sum_ / static_cast<double>(samples_) : 0.0, samples_);
  }

 private:
  std::uint64_t every_;
  double sum_ = 0;
  std::uint64_t samples_ = 0;
};

void install_moments(Installation& in) {
  const MomentsSpec* spec = in.spec.model<MomentsSpec>("analysis.test_moments");
  if (!spec) return;
  Moments& m = in.stages.add(StagePoint::EndOfStep, std::make_unique<Moments>(spec->every));
  in.thermo_columns.push_back({"v4_ratio", [](const StepContext& ctx) { return v4_ratio(ctx); }});
  in.sections.push_back({"test_moments", [&m](ByteWriter& w) { m.save(w); },
                                   [&m](ByteReader& r, const std::string&) { m.load(r); }});
  in.summaries.push_back([&m](const StepContext& ctx) { return ctx.comm.root() ? m.summary() : std::string(); });
}

}  // namespace

double v4_ratio(const StepContext& ctx) {
  const ParticleData& p = ctx.particles;
  // sum v^2 and sum v^4 in 2^20 fixed point, and the count: integer sums, the same on any rank count.
  constexpr double kScale = 1048576.0;
  std::int64_t s[3] = {0, 0, static_cast<std::int64_t>(p.n_local)};
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const double v2 = p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    s[0] += std::llround(v2 * kScale);
    s[1] += std::llround(v2 * v2 * kScale);
  }
  ctx.comm.sum(std::span<std::int64_t>(s, 3));
  const double n = static_cast<double>(s[2]);
  const double m2 = static_cast<double>(s[0]) / kScale / n, m4 = static_cast<double>(s[1]) / kScale / n;
  return m4 / (m2 * m2);
}

Model moments_model() {
  return {"test_moments", install_moments, [] { return model_section(moments_keys()); }};
}

}  // namespace mesodpd::test_models
