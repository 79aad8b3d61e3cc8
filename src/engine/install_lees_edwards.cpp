// [lees_edwards]: shear flow of a bulk fluid through Lees-Edwards images (core/box.hpp, ShearImages;
// seed 002 calls it "the classical method" for shear). The model imposes the images (Model::shear),
// gives a new run the linear velocity profile, and measures the shear stress: the viscosity eta(shear
// rate) of steady shear, or the storage and loss moduli G'(omega), G''(omega) of oscillatory shear.
//
// The stress is the (flow, gradient) component of the pressure tensor with the particles' velocities
// taken relative to the imposed profile u_f = rate(t) (x_g - L_g/2):
//   P_fg = (1/V) [ sum_i m_i (v_f - u_f) v_g + sum_pairs (r_ij)_f (F_ij)_g ],   sigma = -P_fg,
// split into its kinetic and its pair (configurational, bonds included) part. Steady shear gives
// eta = sigma / rate; oscillatory shear, strain gamma_0 sin(omega t), gives
// G' = (2/gamma_0) <sigma sin(omega t)> and G'' = (2/gamma_0) <sigma cos(omega t)>, averaged over
// the samples after `equilibrate` (choose a run of whole periods). Errors are block standard errors.
//
// Oscillatory shear also needs the bulk to follow the imposed profile as the rate changes: the images
// alone would move only the fluid within a penetration depth sqrt(2 nu / omega) of the gradient faces.
// The SLLOD equations of motion (Evans & Morriss, Statistical Mechanics of Nonequilibrium Liquids, ch.
// 6), written for the lab-frame velocity v = p/m + rate(t) (x_g - L_g/2) e_f, become Newton's with one
// more force, m (d rate/dt) (x_g - L_g/2) e_f: a Forces stage adds it (zero for steady shear).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "analysis/block_rows.hpp"
#include "engine/installer.hpp"
#include "engine/lees_edwards_spec.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "integrate/thermostat_keys.hpp"
#include "io/atomic_file.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"
#include "neighbor/cell_grid.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

constexpr double kMaxImageStep = 0.1;
__extension__ using Int128 = __int128;
constexpr double kKineticScale = 1099511627776.0;  // 2^40  // images move at most this fraction of the largest cutoff per step

const keys::KeyTable<LeesEdwardsSpec>& lees_edwards_keys() {
  using T = LeesEdwardsSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("lees_edwards");
    t.axis("flow", &T::flow, "The flow axis f: the images along the gradient axis slide along it.").default_text("\"x\"");
    t.axis("gradient", &T::gradient,
           "The gradient axis g, after the flow axis (xy, xz or yz): the flow velocity grows along it.")
        .default_text("\"y\"");
    t.number("shear_rate", &T::shear_rate, keys::kFinite,
             "Steady shear: the rate dv_f/dx_g. The image one box length up g moves at rate L_g along f.")
        .default_text("(none: give it, or strain_amplitude and omega)");
    t.number("strain_amplitude", &T::strain_amplitude, keys::kPositive,
             "Oscillatory shear: the amplitude gamma_0 of the strain gamma(t) = gamma_0 sin(omega t).")
        .default_text("(none)");
    t.number("omega", &T::omega, keys::kPositive,
             "Oscillatory shear: the angular frequency omega. Every mobile particle also feels the homogeneous-shear "
             "force m (d rate/dt) (x_g - L_g/2) along f (SLLOD), so the whole box follows the strain.")
        .default_text("(none)");
    t.boolean("initial_profile", &T::initial_profile,
              "A new run adds the linear profile rate (x_g - L_g/2) to the initial flow velocities (a run at rest "
              "needs about L_g^2 / nu to develop it).")
        .default_text("true");
    t.integer("stress_every", &T::stress_every, {1, 1000000000},
              "Steps between stress samples (each needs the pair virial of its step).")
        .default_text("10");
    t.integer("equilibrate", &T::equilibrate, {0, 4000000000000000000},
              "Samples at steps up to this one are left out of the averages (the start-up transient).")
        .default_text("0");
    t.integer("blocks", &T::blocks, {2, 10000}, "Blocks of the error estimate (block standard error).")
        .default_text("10");
    return t;
  }();
  return table;
}

const char* axis_name(int a) { return a == 0 ? "x" : (a == 1 ? "y" : "z"); }

void check_lees_edwards(const LeesEdwardsSpec& s, const SimulationSpec& spec) {
  const auto f = static_cast<std::size_t>(s.flow), g = static_cast<std::size_t>(s.gradient);
  if (s.flow == s.gradient)
    throw SpecError("lees_edwards.gradient", fmt::format("\"{}\"", axis_name(s.gradient)),
                    "must differ from the flow axis");
  if (s.flow > s.gradient)
    throw SpecError("lees_edwards.flow", fmt::format("\"{}\"", axis_name(s.flow)),
                    fmt::format("must come before the gradient axis \"{}\": the planes are xy, xz or yz (swap the two "
                                "axes of the box to shear along {}{})",
                                axis_name(s.gradient), axis_name(s.flow), axis_name(s.gradient)));
  for (const std::size_t a : {f, g})
    if (!spec.periodic[a])
      throw SpecError("system.periodic", "",
                      fmt::format("Lees-Edwards shear needs the {} axis {} periodic; walls may close only the third axis",
                                  a == f ? "flow" : "gradient", axis_name(static_cast<int>(a))));
  const bool steady = s.shear_rate.has_value();
  if (steady && (s.omega || s.strain_amplitude))
    throw SpecError("lees_edwards.shear_rate", fmt::format("{}", *s.shear_rate),
                    "steady shear (shear_rate) and oscillatory shear (strain_amplitude, omega) exclude each other");
  if (!steady && !(s.omega && s.strain_amplitude))
    throw SpecError(s.omega ? "lees_edwards.strain_amplitude" : (s.strain_amplitude ? "lees_edwards.omega" : "lees_edwards.shear_rate"),
                    "", "is required: give shear_rate (steady shear) or both strain_amplitude and omega (oscillatory)");
  if (steady && *s.shear_rate == 0.0)
    throw SpecError("lees_edwards.shear_rate", "0", "must not be zero (an unsheared box is a plain periodic one)");
  if (spec.poiseuille.enabled)
    throw SpecError("poiseuille", "", "a reverse-Poiseuille flow and a Lees-Edwards shear cannot share the box");
  // The equilibrium analyses unwrap positions with whole box lengths (a crossing of the sheared faces
  // would jump by the image offset) and correlate velocities that carry the imposed flow: in a sheared
  // box they would measure the shear, not the fluid's diffusion or Green-Kubo viscosity.
  if (spec.msd.enabled)
    throw SpecError("analysis.msd", "",
                    "is not measured under Lees-Edwards shear (the unwrapped positions would jump by the image offset "
                    "and the flow would dominate the displacement); measure diffusion in an unsheared run");
  if (spec.models.count("analysis.transport"))
    throw SpecError("analysis.transport", "",
                    "is not measured under Lees-Edwards shear (the VACF and the MSD would follow the imposed flow, and "
                    "Green-Kubo needs equilibrium); the sheared run's own viscosity is in shear_summary.csv");
  if (spec.bond_subcycles > 1)
    throw SpecError("bonds.subcycles", fmt::format("{}", spec.bond_subcycles),
                    "is not supported with Lees-Edwards shear (the inner steps would see the image offset of the "
                    "step's start); use 1");
  if (spec.species.empty() || spec.pairs.empty()) return;  // validate() reports those
  const double rc = max_cutoff(make_pair_laws(spec));
  const double u = s.max_image_velocity(spec);
  if (u * spec.dt > kMaxImageStep * rc)
    throw SpecError(steady ? "lees_edwards.shear_rate" : "lees_edwards.strain_amplitude", "",
                    fmt::format("the images would move {:.4g} per step (rate {:.4g} x L_{} {:.4g} x dt {:.4g}), more than "
                                "{} of the largest cutoff {:.4g}; lower the rate or dt",
                                u * spec.dt, u / spec.box[g], axis_name(s.gradient), spec.box[g], spec.dt,
                                kMaxImageStep, rc));
  // The shifted stencil needs four cells along the flow axis and three along the gradient axis.
  const double skin = spec.neighbor == NeighborMethod::Verlet ? spec.skin : 0.0;
  Box box;
  box.len = {spec.box[0], spec.box[1], spec.box[2]};
  const std::array<int, 3> cells = CellGrid::dims_for(box, std::max(rc, spec.bond_reach) + skin);
  if (cells[f] < 4 || cells[g] < 3)
    throw SpecError("system.box", "",
                    fmt::format("Lees-Edwards shear needs at least 4 neighbour cells along the flow axis and 3 along the "
                                "gradient axis; cells of {:.4g} give {} along {} and {} along {}",
                                std::max(rc, spec.bond_reach) + skin, cells[f], axis_name(s.flow), cells[g],
                                axis_name(s.gradient)));
}

std::optional<ShearImages> shear_images(const SimulationSpec& spec) {
  const LeesEdwardsSpec* s = spec.model<LeesEdwardsSpec>("lees_edwards");
  if (!s) return std::nullopt;
  check_lees_edwards(*s, spec);
  ShearImages im;
  im.flow = s->flow;
  im.gradient = s->gradient;
  if (s->oscillatory()) {
    im.strain_amplitude = *s->strain_amplitude;
    im.omega = *s->omega;
  } else {
    im.rate = *s->shear_rate;
  }
  return im;
}

// The stress of one sample: kinetic and pair parts of sigma_fg = -P_fg, and the normal stress
// differences N1 = sigma_ff - sigma_gg and N2 = sigma_gg - sigma_vv (v the third, vorticity, axis).
// Collective.
struct StressSample {
  double kinetic = 0, pairs = 0, n1 = 0, n2 = 0;
  double total() const { return kinetic + pairs; }
};

// The pair sums' virial holds every force between particles, the pairwise thermostat's impulses and the
// membranes' forces included (core/stage.hpp).
StressSample measure_stress(const StepContext& ctx, int f, int g) {
  const ParticleData& p = ctx.particles;
  const Box& box = ctx.box;
  const int w = 3 - f - g;
  const double* r[3] = {p.x.data(), p.y.data(), p.z.data()};
  const double* v[3] = {p.vx.data(), p.vy.data(), p.vz.data()};
  const double rate = box.shear.current_rate, mid = 0.5 * box.length(g);
  // In 128-bit fixed point (2^40 units), so the sums are the same on any rank count and storage order:
  // m u_f v_g, m u_f^2, m v_g^2, m v_w^2, m, m u_f, m v_g, m v_w with u_f = v_f - rate (x_g - L_g/2). The
  // products are then taken about the mean velocities: a uniform drift is no stress. (The sum of m u_f is
  // a constant of the motion: pair forces cancel, a crossing of the gradient faces leaves u_f unchanged,
  // and d/dt sum m u_f = -rate sum m v_g = 0; it is zero from the initial profile, not from every data
  // file.)
  Int128 k[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  auto fixed = [](double x) { return static_cast<Int128>(x * kKineticScale); };
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (p.body[i] != 0) continue;
    const double m = ctx.species_mass[static_cast<std::size_t>(p.species[i])];
    const double uf = v[f][i] - rate * (r[g][i] - mid), vg = v[g][i], vw = v[w][i];
    k[0] += fixed(m * uf * vg);
    k[1] += fixed(m * uf * uf);
    k[2] += fixed(m * vg * vg);
    k[3] += fixed(m * vw * vw);
    k[4] += fixed(m);
    k[5] += fixed(m * uf);
    k[6] += fixed(m * vg);
    k[7] += fixed(m * vw);
  }
  if (ctx.comm.distributed()) ctx.comm.sum(std::span<Int128>(k, 8));
  double q[8];
  for (int c = 0; c < 8; ++c) q[c] = static_cast<double>(k[c]) / kKineticScale;
  const double mass = q[4] > 0 ? q[4] : 1.0;
  const double kin[4] = {q[0] - q[5] * q[6] / mass, q[1] - q[5] * q[5] / mass, q[2] - q[6] * q[6] / mass,
                         q[3] - q[7] * q[7] / mass};
  const auto off = static_cast<std::size_t>(f == 0 ? (g == 1 ? 3 : 4) : 5);  // PairSums::virial: xx yy zz xy xz yz
  const double vol = box.volume();
  std::array<double, 6> vir{};
  if (ctx.pair_sums) vir = ctx.pair_sums->virial;
  auto diag = [&](int a) { return vir[static_cast<std::size_t>(a)]; };
  StressSample s;
  s.kinetic = -kin[0] / vol;
  s.pairs = -vir[off] / vol;
  // sigma_aa = -P_aa = -(kinetic_aa + virial_aa) / V
  const double sf = -(kin[1] + diag(f)) / vol, sg = -(kin[2] + diag(g)) / vol, sw = -(kin[3] + diag(w)) / vol;
  s.n1 = sf - sg;
  s.n2 = sg - sw;
  return s;
}

// Mean and block standard error of column c of the rows (sums over samples).
struct MeanError {
  double mean = 0, error = 0;
};

class ShearStress final : public Stage {
 public:
  // kinetic, pairs, then each times sin and times cos, then N1 and N2
  static constexpr std::size_t kWidth = 8;
  explicit ShearStress(const LeesEdwardsSpec& s) : spec_(s), blocks_(kWidth, static_cast<std::size_t>(s.blocks)) {}

  bool wants_pair_sums(std::uint64_t step) const override { return step % spec_.stress_every == 0; }
  void run(StepContext& ctx) override {
    if (ctx.step % spec_.stress_every != 0 || ctx.step <= spec_.equilibrate) return;
    const StressSample s = measure_stress(ctx, spec_.flow, spec_.gradient);
    const double t = static_cast<double>(ctx.step) * ctx.dt;
    const double w = spec_.oscillatory() ? *spec_.omega : 0.0;
    const double sn = std::sin(w * t), cs = std::cos(w * t);
    const double row[kWidth] = {s.kinetic, s.pairs, s.kinetic * sn, s.pairs * sn, s.kinetic * cs, s.pairs * cs, s.n1, s.n2};
    blocks_.add(row);
    for (std::size_t c = 0; c < kWidth; ++c) total_[c] += row[c];
    ++samples_;
  }

  // The mean of a combination a . row over all samples, and its block standard error.
  MeanError estimate(const std::array<double, kWidth>& a) const {
    MeanError e;
    if (samples_ == 0) return e;
    for (std::size_t c = 0; c < kWidth; ++c) e.mean += a[c] * total_[c];
    e.mean /= static_cast<double>(samples_);
    const std::size_t nb = blocks_.full_blocks();
    if (nb < 2) return e;
    double s1 = 0, s2 = 0;
    for (std::size_t k = 0; k < nb; ++k) {
      double v = 0;
      for (std::size_t c = 0; c < kWidth; ++c) v += a[c] * blocks_.block(k)[c];
      v /= static_cast<double>(blocks_.samples_per_block());
      s1 += v;
      s2 += v * v;
    }
    const double mean = s1 / static_cast<double>(nb);
    const double var = std::max(0.0, s2 / static_cast<double>(nb) - mean * mean);
    e.error = std::sqrt(var / static_cast<double>(nb - 1));
    return e;
  }
  std::uint64_t samples() const { return samples_; }
  const LeesEdwardsSpec& spec() const { return spec_; }

  void save(ByteWriter& w) const {
    w.put<std::int32_t>(spec_.flow);
    w.put<std::int32_t>(spec_.gradient);
    w.put<double>(spec_.shear_rate.value_or(0.0));
    w.put<double>(spec_.strain_amplitude.value_or(0.0));
    w.put<double>(spec_.omega.value_or(0.0));
    w.put<std::uint64_t>(samples_);
    for (double v : total_) w.put<double>(v);
    blocks_.save(w);
  }
  void load(ByteReader& r, const std::string& context) {
    const int f = r.get<std::int32_t>(), g = r.get<std::int32_t>();
    const double rate = r.get<double>(), amp = r.get<double>(), om = r.get<double>();
    if (f != spec_.flow || g != spec_.gradient || rate != spec_.shear_rate.value_or(0.0) ||
        amp != spec_.strain_amplitude.value_or(0.0) || om != spec_.omega.value_or(0.0))
      throw ConfigError(fmt::format("lees_edwards: the checkpoint {} was sheared along {}{} with shear_rate {}, "
                                    "strain_amplitude {}, omega {}; a restart continues only the same shear",
                                    context, axis_name(f), axis_name(g), rate, amp, om),
                        "lees_edwards");
    samples_ = r.get<std::uint64_t>();
    for (double& v : total_) v = r.get<double>();
    blocks_.load(r, context);
  }

 private:
  LeesEdwardsSpec spec_;
  BlockRows blocks_;
  std::array<double, kWidth> total_{};
  std::uint64_t samples_ = 0;
};

// The homogeneous-shear force of oscillatory shear (SLLOD, see the top): m (d rate / dt) (x_g - L_g/2)
// along f on every mobile particle, with d rate / dt = -gamma_0 omega^2 sin(omega t).
class HomogeneousShearForce final : public Stage {
 public:
  HomogeneousShearForce(int flow, int gradient, double amplitude, double omega)
      : f_(flow), g_(gradient), amplitude_(amplitude), omega_(omega) {}
  void run(StepContext& ctx) override {
    ParticleData& p = ctx.particles;
    const double t = static_cast<double>(ctx.step) * ctx.dt;
    const double accel = -amplitude_ * omega_ * omega_ * std::sin(omega_ * t), mid = 0.5 * ctx.box.length(g_);
    std::vector<double>& ff = f_ == 0 ? p.fx : (f_ == 1 ? p.fy : p.fz);
    const std::vector<double>& xg = g_ == 0 ? p.x : (g_ == 1 ? p.y : p.z);
    const std::size_t n = p.n_local;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      if (p.body[i] == 0) ff[i] += ctx.species_mass[static_cast<std::size_t>(p.species[i])] * accel * (xg[i] - mid);
  }

 private:
  int f_, g_;
  double amplitude_, omega_;
};

std::string format_estimate(const MeanError& e) { return fmt::format("{:.5g} +- {:.2g}", e.mean, e.error); }

}  // namespace

ModelSection lees_edwards_section() { return model_section(lees_edwards_keys(), check_lees_edwards); }
std::optional<ShearImages> lees_edwards_images(const SimulationSpec& spec) { return shear_images(spec); }

std::string lees_edwards_numbers(const SimulationSpec& spec) {
  const LeesEdwardsSpec* s = spec.model<LeesEdwardsSpec>("lees_edwards");
  if (!s) return "";
  const double u = s->max_image_velocity(spec);
  return fmt::format("lees_edwards: images along {} slide along {} at up to {:.4g} ({:.4g} per step, {:.3g} of the "
                     "thermal speed sqrt(kT/m) of species 0)\n",
                     axis_name(s->gradient), axis_name(s->flow), u, u * spec.dt,
                     spec.species.empty() ? 0.0 : u / std::sqrt(spec.kT / spec.species[0].mass));
}

void install_lees_edwards(Installation& in) {
  const LeesEdwardsSpec* s = in.spec.model<LeesEdwardsSpec>("lees_edwards");
  if (!s) return;
  check_lees_edwards(*s, in.spec);
  const Box& box = in.sim.box();
  if (!box.sheared()) throw std::logic_error("[lees_edwards] without the box's shear images");
  if (in.spec.model<ThermostatSpec>("thermostat")) {
    const double rc = in.spec.model<ThermostatSpec>("thermostat")->rc;
    if (box.length(s->gradient) < 3 * rc)
      throw SpecError("system.box", "",
                      fmt::format("Lees-Edwards shear with [thermostat] needs the gradient axis at least 3 thermostat.rc = "
                                  "{:.4g} long",
                                  3 * rc));
  }
  ParticleData& p = in.sim.particles();
  if (!in.restarted && s->initial_profile) {
    // The linear profile, zero at the middle of the gradient axis: mobile particles only.
    const double rate = s->initial_rate(), mid = 0.5 * box.length(s->gradient);
    std::vector<double>& vf = s->flow == 0 ? p.vx : (s->flow == 1 ? p.vy : p.vz);
    const std::vector<double>& xg = s->gradient == 0 ? p.x : (s->gradient == 1 ? p.y : p.z);
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.body[i] == 0) vf[i] += rate * (xg[i] - mid);
  }
  if (s->oscillatory())
    in.stages.add(StagePoint::Forces,
                  std::make_unique<HomogeneousShearForce>(s->flow, s->gradient, *s->strain_amplitude, *s->omega));
  auto& stress = in.stages.add(StagePoint::EndOfStep, std::make_unique<ShearStress>(*s));
  in.sections.push_back({"lees_edwards", [&stress](ByteWriter& w) { stress.save(w); },
                         [&stress](ByteReader& r, const std::string& context) { stress.load(r, context); }});
  const int f = s->flow, g = s->gradient;
  in.thermo_columns.push_back({"shear_stress", [f, g](const StepContext& ctx) { return measure_stress(ctx, f, g).total(); }});
  in.thermo_columns.push_back({"shear_offset", [](const StepContext& ctx) { return ctx.box.shear.offset; }});
  const std::filesystem::path out = in.options.out_dir;
  in.summaries.push_back([&stress, out](const StepContext& ctx) -> std::string {
    const LeesEdwardsSpec& sp = stress.spec();
    const std::string plane = std::string(axis_name(sp.flow)) + axis_name(sp.gradient);
    if (stress.samples() == 0)
      return fmt::format("lees_edwards: no stress sample after step {} (lees_edwards.equilibrate)\n", sp.equilibrate);
    std::string text;
    std::vector<std::pair<std::string, MeanError>> rows;
    if (!sp.oscillatory()) {
      const double rate = *sp.shear_rate;
      const MeanError kin = stress.estimate({1 / rate, 0, 0, 0, 0, 0, 0, 0}), pair = stress.estimate({0, 1 / rate, 0, 0, 0, 0, 0, 0});
      const MeanError eta = stress.estimate({1 / rate, 1 / rate, 0, 0, 0, 0, 0, 0});
      const MeanError sigma = stress.estimate({1, 1, 0, 0, 0, 0, 0, 0});
      const MeanError n1 = stress.estimate({0, 0, 0, 0, 0, 0, 1, 0}), n2 = stress.estimate({0, 0, 0, 0, 0, 0, 0, 1});
      rows = {{"shear_stress", sigma}, {"eta", eta},    {"eta_kinetic", kin}, {"eta_pairs", pair},
              {"N1", n1},              {"N2", n2},
              {"Psi1", {n1.mean / (rate * rate), n1.error / (rate * rate)}}};
      text = fmt::format("lees_edwards: steady shear {} at rate {:.4g}: stress {}, viscosity eta = {} (kinetic {}, "
                         "pairs {}), normal stress differences N1 = {}, N2 = {} from {} samples\n",
                         plane, rate, format_estimate(sigma), format_estimate(eta), format_estimate(kin),
                         format_estimate(pair), format_estimate(n1), format_estimate(n2), stress.samples());
    } else {
      const double a = 2 / *sp.strain_amplitude;
      const MeanError g1 = stress.estimate({0, 0, a, a, 0, 0, 0, 0}), g2 = stress.estimate({0, 0, 0, 0, a, a, 0, 0});
      const MeanError g1p = stress.estimate({0, 0, 0, a, 0, 0, 0, 0}), g2p = stress.estimate({0, 0, 0, 0, 0, a, 0, 0});
      const MeanError g1k = stress.estimate({0, 0, a, 0, 0, 0, 0, 0}), g2k = stress.estimate({0, 0, 0, 0, a, 0, 0, 0});
      rows = {{"G_storage", g1},           {"G_loss", g2},           {"G_storage_kinetic", g1k},
              {"G_loss_kinetic", g2k},     {"G_storage_pairs", g1p}, {"G_loss_pairs", g2p},
              {"eta_dynamic", {g2.mean / *sp.omega, g2.error / *sp.omega}}};
      text = fmt::format("lees_edwards: oscillatory shear {} at omega {:.4g}, strain amplitude {:.4g}: G' = {}, G'' = {} "
                         "(eta' = G''/omega = {:.5g}) from {} samples\n",
                         plane, *sp.omega, *sp.strain_amplitude, format_estimate(g1), format_estimate(g2),
                         g2.mean / *sp.omega, stress.samples());
    }
    if (!out.empty() && ctx.comm.root())
      write_file_atomically(out / "shear_summary.csv", [&](std::ostream& o) {
        o << "quantity,value,error\n";
        for (const auto& [name, e] : rows) o << fmt::format("{},{:.10g},{:.4g}\n", name, e.mean, e.error);
        o << fmt::format("samples,{},0\n", stress.samples());
      });
    return text;
  });
}

}  // namespace mesodpd
