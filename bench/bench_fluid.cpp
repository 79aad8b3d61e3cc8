// Throughput benchmark: particle-steps per second of the standard DPD fluid (rho = 3, a = 25,
// gamma = 4.5, kT = 1, dt = 0.04, modified velocity-Verlet) for chosen sizes, threads and neighbour
// settings; with --system mdpd-slab, of Warren's many-body liquid slab (A = -40, B = 25, r_d = 0.75,
// dt = 0.01: a density pass and a force pass per step) in a box twice as long as the slab.
#include <fmt/format.h>
#include <omp.h>
#include <sys/utsname.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string_view>
#include <fstream>
#include <random>
#include <string>

#include "engine/force_compute.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/validate.hpp"
#include "parallel/comm.hpp"
#include "parallel/openmp_wait.hpp"

namespace {

// Peak resident memory of this process in bytes (VmHWM), the honest measure of bytes per particle.
double proc_status_bytes(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return 1024.0 * std::stod(line.substr(key.size()));
  return 0.0;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

mesodpd::SimulationSpec fluid(std::uint64_t n, double skin, bool verlet) {
  mesodpd::SimulationSpec s;
  const double len = std::cbrt(static_cast<double>(n) / 3.0);
  s.box = {len, len, len};
  s.species.resize(1);
  s.species[0].name = "A";
  s.species[0].count = n;
  s.pairs.resize(1);
  s.dt = 0.04;
  s.skin = skin;
  s.neighbor = verlet ? mesodpd::NeighborMethod::Verlet : mesodpd::NeighborMethod::Cells;
  s.progress = false;
  return s;
}

// Warren's liquid slab of n particles at density 6: a box L x L x 2L with the liquid in |z - L| < L/2,
// written as a LAMMPS data file (random positions, seeded) and read back through the normal input path.
mesodpd::SimulationSpec mdpd_slab(std::uint64_t n, bool verlet, double skin, const std::filesystem::path& data) {
  const double len = std::cbrt(static_cast<double>(n) / 6.0);
  {
    std::mt19937_64 rng(48000);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::ofstream f(data);
    f << "mdpd slab\n\n" << n << " atoms\n1 atom types\n\n0 " << len << " xlo xhi\n0 " << len << " ylo yhi\n0 "
      << 2 * len << " zlo zhi\n\nAtoms\n\n";
    f.precision(10);
    for (std::uint64_t k = 0; k < n; ++k)
      f << k + 1 << " 1 " << len * u(rng) << ' ' << len * u(rng) << ' ' << len * (0.5 + u(rng)) << '\n';
  }
  mesodpd::SimulationSpec s;
  s.box = {len, len, 2 * len};
  s.species.resize(1);
  s.species[0].name = "A";
  s.data_file = data.string();
  s.velocities = mesodpd::VelocityInit::Maxwell;
  s.pair_style = mesodpd::PairStyle::Mdpd;
  s.pair_section.params.a = -40.0;
  s.pair_section.params.own["b"] = 25.0;
  s.pair_section.params.rd = 0.75;
  s.dt = 0.01;
  s.skin = skin;
  s.neighbor = verlet ? mesodpd::NeighborMethod::Verlet : mesodpd::NeighborMethod::Cells;
  s.progress = false;
  mesodpd::validate(s);
  return s;
}

// The pair style of the law named `name` in the engine's list.
mesodpd::PairStyle style_named(std::string_view name) {
  const auto& laws = mesodpd::pair_law_infos();
  for (std::size_t k = 0; k < laws.size(); ++k)
    if (laws[k].style == name) return static_cast<mesodpd::PairStyle>(k);
  throw std::logic_error("no pair law named " + std::string(name));
}

// The smoothed-DPD fluid of examples/sdpd_fluid (number density 3, eta = 1, c = 8, kT = 0.1,
// dt = 0.01) over the kernel cutoff rc (1.5: 42 neighbours); with `as_dpd`, the standard DPD fluid
// (a = 25, gamma = 4.5) with the same cutoff for both forces, so the same N and neighbour count.
mesodpd::SimulationSpec sdpd(std::uint64_t n, double rc, bool verlet, double skin, bool as_dpd) {
  mesodpd::SimulationSpec s = fluid(n, skin, verlet);
  s.dt = 0.01;
  s.pair_section.params.rc = rc;
  if (!as_dpd) {
    s.kT = 0.1;
    s.pair_style = style_named("sdpd");
    s.pair_section.params.own = {{"eta", 1.0}, {"c", 8.0}, {"rho0", 3.0}};
  }
  s.pairs.clear();
  mesodpd::validate(s);
  return s;
}

// The fluid above with single-particle DPD (pair.style = "spdpd"): particles of radius 0.5 with
// gamma_perp = gamma = 4.5, so the spins, the non-central friction and the torques cost their share.
mesodpd::SimulationSpec spdpd(std::uint64_t n, double skin, bool verlet) {
  mesodpd::SimulationSpec s = fluid(n, skin, verlet);
  s.pair_style = style_named("spdpd");
  s.pair_section.params.own = {{"gamma_perp", 4.5}};
  s.species[0].own = {{"radius", 0.5}};
  s.pairs.clear();
  mesodpd::validate(s);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  // The same OpenMP wait policy as the mesodpd program (docs/performance.md, "Busy machines").
  mesodpd::bound_openmp_spin_wait(argv);
  mesodpd::MpiSession mpi(argc, argv);
  const mesodpd::Comm comm = mesodpd::Comm::world();
  CLI::App app{"mesodpd fluid throughput benchmark (under mpirun: strong scaling, or weak with --per-rank)"};
  bool per_rank = false;
  std::vector<std::uint64_t> sizes{3000, 98304};
  std::vector<int> threads{1, 2};
  int steps = 200, warmup = 50;
  double skin = 0.3;
  std::string method = "cells", system = "fluid";
  app.add_option("--n", sizes, "particle counts (box chosen for rho = 3)");
  app.add_option("--threads", threads, "thread counts");
  app.add_option("--steps", steps, "timed steps");
  app.add_option("--warmup", warmup, "untimed steps first (equilibrates the random start)");
  app.add_option("--skin", skin, "Verlet skin");
  app.add_option("--method", method, "verlet | cells")->check(CLI::IsMember({"verlet", "cells"}));
  double sdpd_rc = 1.5;
  app.add_option("--sdpd-rc", sdpd_rc, "kernel cutoff of --system sdpd and dpd-rc (1.5: 42 neighbours)");
  app.add_option("--system", system,
                 "fluid (rho = 3 DPD) | mdpd-slab (Warren's liquid slab, density 6) | sdpd (smoothed DPD, rho = 3) | "
                 "dpd-rc (DPD with the cutoff --sdpd-rc) | spdpd (the fluid with single-particle DPD's spins)")
      ->check(CLI::IsMember({"fluid", "mdpd-slab", "sdpd", "dpd-rc", "spdpd"}));
  app.add_flag("--per-rank", per_rank, "--n is per MPI rank (weak scaling) instead of in total");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return comm.root() ? app.exit(e) : 1;
  }
  // Only the root prints; the others run silently.
  auto print = [&]<class... A>(fmt::format_string<A...> f, A&&... args) {
    if (comm.root()) fmt::print(f, std::forward<A>(args)...);
  };

  // Bad settings (a MESODPD_SIMD value, a size the engine refuses) end with one message and exit 1.
  try {
    utsname u{};
    uname(&u);
    print("# machine: {} ({} logical CPUs), {} {}, {} MPI rank(s)\n", cpu_model(), omp_get_num_procs(), u.sysname,
          u.release, comm.size());
  #ifdef MESODPD_SINGLE_PRECISION
    constexpr const char* kPrecision = "single-precision pair arithmetic (MESODPD_SINGLE)";
  #else
    constexpr const char* kPrecision = "double precision";
  #endif
    if (system == "fluid" || system == "spdpd")
      print("# {} rho=3 a=25 gamma=4.5{} kT=1 dt=0.04 GW lambda=0.5, {}, method={} skin={}\n", system,
            system == "spdpd" ? " gamma_perp=4.5 radius=0.5" : "", kPrecision, method, method == "verlet" ? skin : 0.0);
    else if (system == "sdpd" || system == "dpd-rc")
      print("# {} rho=3 rc={} ({:.0f} neighbours) dt=0.01{}, {}, method={} skin={}\n", system, sdpd_rc,
            3.0 * 4.18879 * sdpd_rc * sdpd_rc * sdpd_rc, system == "sdpd" ? " eta=1 c=8 kT=0.1 Lucy" : " a=25 gamma=4.5",
            kPrecision, method, method == "verlet" ? skin : 0.0);
    else
      print("# mdpd slab (liquid rho~6 in half the box) A=-40 B=25 rc=1 rd=0.75 gamma=4.5 kT=1 dt=0.01 GW lambda=0.5 "
            "Warren kernel, {}, method={} skin={}\n", kPrecision, method, method == "verlet" ? skin : 0.0);
    print("# OpenMP wait: {}\n", mesodpd::openmp_wait_description());
    print("# pair loop SIMD target: {} (chosen at run time; MESODPD_SIMD caps it)\n", mesodpd::ForceCompute::simd_target());
    print("{:>9} {:>5} {:>7} {:>7} {:>16} {:>12} {:>9} {:>11} {:>9} {:>9} {:>7} {:>7}\n", "N", "ranks", "threads",
          "steps", "particle-steps/s", "ns/particle", "rebuilds", "peakRSS/N", "RSS/N", "grid", "comm%", "msg%");
    for (std::uint64_t n : sizes)
      for (int t : threads) {
        omp_set_num_threads(t);
        const std::uint64_t total = per_rank ? n * static_cast<std::uint64_t>(comm.size()) : n;
        const auto data = std::filesystem::temp_directory_path() / fmt::format("bench_mdpd_slab_{}_r{}.data", total, comm.rank());
        mesodpd::Simulation sim(system == "fluid"    ? fluid(total, skin, method == "verlet")
                                : system == "spdpd"  ? spdpd(total, skin, method == "verlet")
                                : system == "sdpd"   ? sdpd(total, sdpd_rc, method == "verlet", skin, false)
                                : system == "dpd-rc" ? sdpd(total, sdpd_rc, method == "verlet", skin, true)
                                                     : mdpd_slab(total, method == "verlet", skin, data),
                                mesodpd::RunOptions{});
        for (int k = 0; k < warmup; ++k) sim.step();
        const auto b0 = sim.neighbor_list().builds();
        comm.barrier();
        const double c0 = sim.halo().seconds(), m0 = sim.halo().message_seconds();
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < steps; ++k) sim.step();
        comm.barrier();
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        // Communication share: the largest per-rank time in migration, ghosts and reverse forces (which
        // includes waiting for slower neighbours) over the wall time.
        const double comm_secs =
            static_cast<double>(comm.max(static_cast<std::uint64_t>((sim.halo().seconds() - c0) * 1e9))) * 1e-9;
        const double msg_secs =
            static_cast<double>(comm.max(static_cast<std::uint64_t>((sim.halo().message_seconds() - m0) * 1e9))) * 1e-9;
        const double np = static_cast<double>(sim.total_particles());
        const double rate = np * steps / secs;
        const double local = static_cast<double>(sim.particles().n_local);
        const auto& g = sim.halo().decomposition().grid;
        // Peak RSS covers the whole process (all earlier runs too), so run the largest N last or alone.
        // Memory columns are the root rank's, per particle it owns.
        print("{:>9} {:>5} {:>7} {:>7} {:>16.4g} {:>12.1f} {:>9} {:>11.0f} {:>9.0f} {:>9} {:>7.1f} {:>7.1f}\n",
              sim.total_particles(), comm.size(), t, steps, rate, 1e9 / rate, sim.neighbor_list().builds() - b0,
              proc_status_bytes("VmHWM:") / local, proc_status_bytes("VmRSS:") / local,
              fmt::format("{}x{}x{}", g[0], g[1], g[2]), 100.0 * comm_secs / secs, 100.0 * msg_secs / secs);
        if (comm.root()) std::fflush(stdout);
        // A law with a density pass: the share of the density pass in the two pair passes, timed apart on
        // a copy of the final state (one rank: no ghosts).
        if (const auto density = mesodpd::make_density_settings(sim.spec()); density && comm.size() == 1) {
          mesodpd::ParticleData p = sim.particles();
          mesodpd::ForceCompute fc(mesodpd::make_pair_laws(sim.spec()), mesodpd::NoiseSettings{7, mesodpd::NoiseKind::Uniform});
          std::vector<double> rho(p.size());
          mesodpd::PairSums sums;
          const int reps = 50;
          auto timed = [&](auto&& f) {
            const auto a = std::chrono::steady_clock::now();
            for (int k = 0; k < reps; ++k) f(k);
            return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
          };
          const double td = timed([&](int) { fc.compute_density(p, sim.box(), sim.neighbor_list(), *density, rho, nullptr); });
          const double tf = timed([&](int k) {
            fc.compute(p, sim.box(), sim.neighbor_list(), static_cast<std::uint64_t>(k), sim.spec().dt, false, sums, nullptr,
                       rho.data());
          });
          print("#   density pass {:.3g} ms, force pass {:.3g} ms: the density pass is {:.1f}% of the pair passes, "
                "{:.1f}% of the step\n",
                1e3 * td / reps, 1e3 * tf / reps, 100.0 * td / (td + tf), 100.0 * (td / reps) / (secs / steps));
        }
      }
  } catch (const std::exception& e) {
    if (comm.root()) fmt::print(stderr, "bench_fluid: {}\n", e.what());
    return 1;
  }
  return 0;
}
