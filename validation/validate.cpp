// mesodpd-validate: long physical-validation runs (temperature control, equation of state, ideal-gas g(r),
// reverse-Poiseuille viscosity) printed as markdown tables for docs/validation.md. The same measurement
// bodies (physics_checks.hpp) run, shorter and with asserted tolerances, in
// tests/physics/test_validation.cpp.
#include <fmt/format.h>
#include <omp.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "physics_checks.hpp"

namespace {

using namespace mesodpd;
using namespace mesodpd::validation;

std::string g_command;  // the command line, echoed above every table

// Run lengths in DPD time units, converted to steps for a given dt.
RunLength lengths(double dt, double equil_time, double prod_time, double sample_time, int blocks) {
  RunLength r;
  r.equil = static_cast<std::uint64_t>(std::llround(equil_time / dt));
  r.prod = static_cast<std::uint64_t>(std::llround(prod_time / dt));
  r.every = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(sample_time / dt)));
  return r.blocks = blocks, r;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void header(const std::string& title) { fmt::print("\n### {}\n\n```\n{}\n```\n\n", title, g_command); }

// ---------------------------------------------------------------------------------------------------------
void temperature(bool quick) {
  FluidCase c;  // rho = 3, a = 25, gamma = 4.5 (sigma = 3), kT = 1, s = 2
  c.lx = c.ly = c.lz = 10.0;
  const double equil = 20.0, prod = quick ? 40.0 : 400.0, sample = 0.1;
  const int blocks = 20;
  header("Temperature control of the modified velocity-Verlet integrator (seed 000 Eq. 10, Sect. 2.5.2)");
  fmt::print(
      "rho = {}, a = {}, gamma = {} (sigma = 3), kT = 1, s = 2, N = {}, box {}^3, seed {}; equilibration {} "
      "time units, production {} time units, kT sampled every {} time units, error = block standard error "
      "({} blocks).\n\n",
      c.rho, c.a, c.gamma, std::llround(c.rho * c.lx * c.ly * c.lz), c.lx, c.seed, equil, prod, sample,
      blocks);
  fmt::print("| lambda | dt | steps | <kT> | std. error | deviation from 1 |\n|---|---|---|---|---|---|\n");
  for (double lambda : {0.5, 0.65})
    for (double dt : {0.01, 0.04, 0.06}) {
      FluidCase k = c;
      k.lambda = lambda;
      k.dt = dt;
      const RunLength rl = lengths(dt, equil, prod, sample, blocks);
      const auto t0 = std::chrono::steady_clock::now();
      const TemperatureResult r = measure_temperature(k, rl);
      fmt::print("| {} | {} | {} | {:.5f} | {:.5f} | {:+.2f}% |\n", lambda, dt, rl.prod, r.kT.mean, r.kT.err,
                 100.0 * (r.kT.mean - 1.0));
      std::fflush(stdout);
      fmt::print(stderr, "  temperature lambda={} dt={}: {:.1f} s\n", lambda, dt, seconds_since(t0));
    }
}

// ---------------------------------------------------------------------------------------------------------
void eos(bool quick) {
  const double dt = 0.04, equil = 20.0, prod = quick ? 40.0 : 400.0, sample = 0.4;
  const int blocks = 20;
  const std::size_t bins = 200;
  header(
      "Equation of state: alpha(rho) and the virial vs g(r) pressure (seed 000 Eq. 13, seed 003 EOS "
      "integral)");
  fmt::print(
      "a = 25, gamma = 4.5, kT = 1, s = 2, dt = {}, lambda = 0.5, box 8^3 (N = 512 rho), seed 20261123; "
      "equilibration {} time units, production {} time units sampled every {} ({} blocks).\n"
      "alpha = (p_C - p_kin) / (a rho^2) sample by sample, where p_C = ThermoState::pressure_conservative "
      "(kinetic + conservative virial, the dissipative and random virials left out) and p_kin = sum m v^2 / "
      "3V "
      "= rho kT_measured (1 - 1/N); so alpha = (p_C - rho kT_measured) / (a rho^2) with the measured, not "
      "the "
      "target, temperature. Groot-Warren: alpha = 0.101 +- 0.001 (seed 000 Eq. 13).\n"
      "p_rdf = rho kT_measured + (2 pi/3) rho^2 Int_0^1 r F^C(r) g(r) r^2 dr (seed 003; the kinetic term "
      "taken "
      "as p_C's, rho kT_measured (1 - 1/N)), midpoint rule over "
      "{} bins of g(r) on [0, 1), measured per block on the same snapshots as p_C and multiplied by (N-1)/N "
      "(g is normalised by the pair density N(N-1)/V^2). delta = p_rdf - p_C with its block error; 'disc.' "
      "is "
      "p_rdf(bins 2dr) - p_rdf(bins dr), about 3x the discretisation error at dr.\n\n",
      dt, equil, prod, sample, blocks, bins);
  fmt::print(
      "| rho | N | <kT> | p_C | alpha | alpha / 0.101 | p_rdf | delta = p_rdf - p_C | disc. |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (double rho : {3.0, 4.0, 5.0, 6.0, 7.0, 8.0}) {
    FluidCase c;
    c.rho = rho;
    c.lx = c.ly = c.lz = 8.0;
    c.dt = dt;
    const auto t0 = std::chrono::steady_clock::now();
    const EosResult r = measure_eos(c, lengths(dt, equil, prod, sample, blocks), bins);
    fmt::print(
        "| {} | {} | {:.4f} +- {:.4f} | {:.4f} +- {:.4f} | {:.5f} +- {:.1e} | {:.4f} | {:.4f} +- {:.4f} | "
        "{:+.5f} +- {:.5f} | {:+.5f} |\n",
        rho, r.n, r.kT.mean, r.kT.err, r.p_conservative.mean, r.p_conservative.err, r.alpha.mean, r.alpha.err,
        r.alpha.mean / 0.101, r.p_rdf.mean, r.p_rdf.err, r.delta.mean, r.delta.err, r.rdf_disc);
    std::fflush(stdout);
    fmt::print(stderr, "  eos rho={}: {:.1f} s\n", rho, seconds_since(t0));
  }
}

// ---------------------------------------------------------------------------------------------------------
void idealgas(bool quick, const std::vector<double>& dts) {
  const double equil = 10.0, prod = quick ? 100.0 : 1000.0, sample = 2.0;
  const std::size_t bins = 100;
  const double rmax = 4.0;
  header("Ideal gas (a = 0): flatness of g(r)");
  fmt::print(
      "rho = 3, a = 0, gamma = 4.5, kT = 1, s = 2, lambda = 0.5, box 10^3 (N = 3000), seed 20261123; "
      "equilibration {} time units, production {} time units, one g(r) snapshot every {} time units; "
      "{} bins on [0, {}). sigma_b = 1 / sqrt(mu_b), mu_b the expected unordered pair count of bin b "
      "(Poisson); z_b = (g_b - 1) / sigma_b. 'mean g - 1 over r < 1' is count-weighted, with its Poisson "
      "error.\n\n",
      equil, prod, sample, bins, rmax);
  fmt::print(
      "| dt | snapshots | max abs(g - 1) | sigma_b (outer .. inner bin) | max abs(z_b) (at r) | "
      "chi^2 per bin: all, r < 1, r >= 1 | mean g - 1 over r < 1 |\n|---|---|---|---|---|---|---|\n");
  for (double dt : dts) {
    FluidCase c;
    c.a = 0.0;
    c.dt = dt;
    c.lx = c.ly = c.lz = 10.0;
    const auto t0 = std::chrono::steady_clock::now();
    const IdealGasResult r = measure_ideal_gas(c, lengths(c.dt, equil, prod, sample, 2), bins, rmax);
    fmt::print(
        "| {} | {} | {:.4f} | {:.4f} .. {:.3f} | {:.2f} ({:.2f}) | {:.3f}, {:.3f}, {:.3f} | {:+.5f} +- "
        "{:.5f} |\n",
        dt, r.samples, r.max_abs_dev, r.sigma_min, r.sigma_max, r.max_z, r.r_max_z, r.chi2_per_bin,
        r.chi2_inside, r.chi2_outside, r.mean_dev_inside, r.mean_dev_inside_err);
    std::fflush(stdout);
    fmt::print(stderr, "  idealgas dt={}: {:.1f} s\n", dt, seconds_since(t0));
  }
}

// ---------------------------------------------------------------------------------------------------------
// Full: 8 x 8 x 20, g = 0.02 (max shear rate ~0.35 at s = 2), 1600 time units (blocks of ~4.5 tau at s = 2).
// Quick (the configuration of tests/physics/test_validation.cpp): 8 x 8 x 12, g = 0.04, 300 time units.
struct ViscosityOptions {
  double g = 0;  // 0: default for full/quick
  double lxy = 8.0;
  double lz = 0;    // 0: default
  double prod = 0;  // 0: default
  std::vector<double> s{2.0, 1.0, 0.5};
  bool check_force = false;
};

void viscosity(bool quick, const ViscosityOptions& o) {
  FluidCase c;
  c.lx = c.ly = o.lxy;
  c.lz = o.lz > 0 ? o.lz : (quick ? 12.0 : 20.0);
  const double g = o.g > 0 ? o.g : (quick ? 0.04 : 0.02);
  const double equil = 100.0, prod = o.prod > 0 ? o.prod : (quick ? 300.0 : 1600.0);
  const int blocks = 10;
  header(
      "Shear viscosity from reverse Poiseuille flow (seed 002) vs kinetic theory (seed 000 Eq. 16, Table 1)");
  fmt::print(
      "rho = 3, a = 25, gamma = 4.5, kT = 1, dt = 0.04, lambda = 0.5, box {} x {} x {} (N = {}), flow x, "
      "gradient z, 40 bins, force g = {} per unit mass, seed {}; equilibration {} time units, profile "
      "sampled every step for {} time units; eta from the fit to the whole-run profile, its error from "
      "{} equal blocks fitted separately. Kinetic theory = rho D / 2 + eta_D with g(r) = 1 (Table 1). "
      "tau = rho (Lz / 2 pi)^2 / eta, the slowest flow mode's relaxation time (a block should be several "
      "tau); gdot = max shear rate rho g Lz / 4 eta; kT_yz = transverse temperature during the flow.\n\n",
      c.lx, c.ly, c.lz, std::llround(c.rho * c.lx * c.ly * c.lz), g, c.seed, equil, prod, blocks);
  fmt::print(
      "| s | eta (measured) | rel. error | kinetic theory | measured / theory | peak flow speed | gdot | "
      "block / tau | kT_yz |\n|---|---|---|---|---|---|---|---|---|\n");
  auto row = [&](const std::string& label, const ViscosityResult& r) {
    fmt::print(
        "| {} | {:.4f} +- {:.4f} | {:.1f}% | {:.4f} | {:.3f} | {:.3f} | {:.3f} | {:.1f} | {:.4f} +- {:.4f} "
        "|\n",
        label, r.eta, r.eta_err, 100.0 * r.eta_err / r.eta, r.eta_kinetic, r.eta / r.eta_kinetic, r.v_max,
        r.shear_rate_max, prod / blocks / r.relax_time, r.kT_transverse.mean, r.kT_transverse.err);
    std::fflush(stdout);
  };
  for (double s : o.s) {
    FluidCase k = c;
    k.s = s;
    const auto t0 = std::chrono::steady_clock::now();
    row(fmt::format("{}", s), measure_viscosity(k, g, lengths(c.dt, equil, prod, 0.4, blocks)));
    fmt::print(stderr, "  viscosity s={}: {:.1f} s\n", s, seconds_since(t0));
  }
  if (!o.check_force) return;
  fmt::print(
      "\nLinear response: s = 2 at g/2 and 2g (same box, seed and run length); first column is g.\n\n"
      "| g | eta (measured) | rel. error | kinetic theory | measured / theory | peak flow speed | gdot | "
      "block / tau | kT_yz |\n|---|---|---|---|---|---|---|---|---|\n");
  for (double gg : {g / 2.0, 2.0 * g}) {
    const auto t0 = std::chrono::steady_clock::now();
    row(fmt::format("{}", gg), measure_viscosity(c, gg, lengths(c.dt, equil, prod, 0.4, blocks)));
    fmt::print(stderr, "  viscosity g={}: {:.1f} s\n", gg, seconds_since(t0));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mesodpd-validate: physical validation runs, printed as markdown tables (docs/validation.md)"};
  app.require_subcommand(1);
  bool quick = false;
  ViscosityOptions vo;
  int threads = 0;
  app.add_option("--threads", threads, "OpenMP threads (default: OMP_NUM_THREADS or all)");
  auto add = [&](const char* name, const char* help) {
    CLI::App* sub = app.add_subcommand(name, help);
    sub->add_flag("--quick", quick, "about 10x shorter runs (larger error bars)");
    return sub;
  };
  CLI::App* t = add("temperature", "mean kT vs dt for lambda = 0.5 and 0.65 (rho = 3, a = 25, gamma = 4.5)");
  CLI::App* e =
      add("eos", "alpha(rho) = (p - rho kT) / (a rho^2) for rho = 3..8, and the g(r) pressure route");
  CLI::App* v = add("viscosity", "reverse Poiseuille viscosity for s = 2, 1, 1/2 vs kinetic theory");
  v->add_flag("--check-force", vo.check_force, "also run s = 2 at g/2 and 2g (linear response)");
  v->add_option("--force", vo.g, "body acceleration g (default 0.02, --quick 0.04)");
  v->add_option("--lxy", vo.lxy, "box length along x and y")->capture_default_str();
  v->add_option("--lz", vo.lz, "box length along the gradient axis z (default 20, --quick 12)");
  v->add_option("--time", vo.prod, "production time in DPD units (default 1600, --quick 300)");
  v->add_option("--s", vo.s, "dissipative weight exponents")->capture_default_str();
  CLI::App* i = add("idealgas", "a = 0: flatness of g(r)");
  std::vector<double> ig_dt{0.04, 0.01};
  i->add_option("--dt", ig_dt, "time steps")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (threads > 0) omp_set_num_threads(threads);

  g_command = "mesodpd-validate";
  for (int k = 1; k < argc; ++k) g_command += std::string(" ") + argv[k];
  fmt::print("<!-- mesodpd {} validation, {} OpenMP thread(s) -->\n", MESODPD_VERSION, omp_get_max_threads());
  const auto t0 = std::chrono::steady_clock::now();
  if (t->parsed()) temperature(quick);
  if (e->parsed()) eos(quick);
  if (v->parsed()) viscosity(quick, vo);
  if (i->parsed()) idealgas(quick, ig_dt);
  fmt::print("\n(wall time {:.0f} s)\n", seconds_since(t0));
  return 0;
}
