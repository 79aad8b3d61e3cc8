// The mesodpd command: `run` a simulation from a TOML config, `check` a config, print the version.
#include <fmt/format.h>
#include <omp.h>

#include <CLI/CLI.hpp>
#include <array>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <new>
#include <optional>
#include <stdexcept>

#include "engine/force_compute.hpp"
#include "engine/initial_state.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/flow_numbers.hpp"
#include "mesodpd/units.hpp"
#include "mesodpd/validate.hpp"
#include "schema/declared_tables.hpp"
#include "parallel/comm.hpp"
#include "parallel/openmp_wait.hpp"

namespace {

constexpr int kExitConfig = 2;
constexpr int kExitBlowUp = 3;

// The value of --steps as a step number. Read as text here because CLI11 clamps an integer that does not
// fit to the type's limit without a word; a step count out of range must be refused instead. The limit
// is that of run.steps, a TOML integer (signed 64-bit).
std::uint64_t parse_steps(const std::string& text) {
  constexpr std::uint64_t kMax = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
  std::uint64_t v = 0;
  const char* end = text.data() + text.size();
  const bool negative = !text.empty() && text[0] == '-';
  const auto [ptr, ec] = std::from_chars(text.data() + (negative ? 1 : 0), end, v);
  if (ptr == text.data() + (negative ? 1 : 0) || ptr != end)
    throw mesodpd::ConfigError(fmt::format("--steps: '{}' is not a whole number of steps", text));
  if (negative && v != 0) throw mesodpd::ConfigError(fmt::format("--steps: {} is negative", text));
  if (ec == std::errc::result_out_of_range || v > kMax)
    throw mesodpd::ConfigError(fmt::format("--steps: {} is too large (at most {})", text, kMax));
  return v;
}

int run_command(const std::string& config, const std::string& out, int threads, std::optional<std::uint64_t> steps,
                const std::string& restart, bool no_progress) {
  using namespace mesodpd;
  if (threads < 0 || threads > kMaxThreads)
    throw ConfigError(fmt::format("--threads: {} is out of range (0 to {})", threads, kMaxThreads));
  SimulationSpec spec = load_config(config);  // validated: what `check` accepts up to here, run accepts too
  const int nthreads = threads > 0 ? threads : (spec.threads > 0 ? spec.threads : omp_get_max_threads());
  omp_set_num_threads(nthreads);
  RunOptions opt;
  opt.out_dir = out;
  if (steps) opt.steps = *steps;
  if (!restart.empty()) {
    if (!std::filesystem::exists(restart)) throw ConfigError(fmt::format("--restart: file {} does not exist", restart));
    opt.restart = restart;
  }
  opt.progress = spec.progress && !no_progress;
  const auto t0 = std::chrono::steady_clock::now();
  const std::array<double, 3> box = spec.box;
  std::optional<Simulation> built;
  try {
    built.emplace(std::move(spec), opt);
  } catch (const BlowUpError& e) {
    // The initial state cannot be integrated (a bond past its maximum length in a data file): the
    // code of a blow-up, found identically on every rank.
    if (Comm::world().root()) fmt::print(stderr, "error: {}\n", e.what());
    return kExitBlowUp;
  } catch (const std::bad_alloc&) {
    // The only refusal before the first step that `check` cannot foresee: memory depends on the
    // machine and, under MPI, on the rank count.
    throw std::runtime_error(fmt::format("out of memory while building the system (box {} x {} x {}); use more MPI "
                                         "ranks or a smaller system.box or particle count",
                                         box[0], box[1], box[2]));
  }
  Simulation& sim = *built;
  const Comm& comm = sim.halo().comm();
  const std::uint64_t first = sim.current_step();
  if (comm.root()) {
    const auto& g = sim.halo().decomposition().grid;
    fmt::print("mesodpd {}: {} particles, box {} x {} x {}, steps {} -> {}, {} rank(s){}, {} thread(s) per rank ({}), "
               "SIMD {}, output in {}\n",
               MESODPD_VERSION, sim.total_particles(), sim.box().len.x, sim.box().len.y, sim.box().len.z, first,
               sim.final_step(), comm.size(), comm.size() > 1 ? fmt::format(" (grid {}x{}x{})", g[0], g[1], g[2]) : "",
               nthreads, openmp_wait_description(), ForceCompute::simd_target(), out);
    for (const std::string& w : spec_warnings(sim.spec())) fmt::print(stderr, "warning: {}\n", w);
    std::fflush(stdout);
  }
  try {
    const std::string summary = sim.run();
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double steps_done = static_cast<double>(sim.final_step() - first);
    if (comm.root()) {
      fmt::print("{}", summary);
      for (const std::string& w : sim.warnings()) fmt::print(stderr, "warning: {}\n", w);
      fmt::print("done: {} steps in {:.1f} s ({:.3g} particle-steps/s)\n", sim.final_step() - first, secs,
                 steps_done * static_cast<double>(sim.total_particles()) / secs);
    }
    // Every output is written; the exit code still tells a script that the numbers ran away.
    if (const auto hot = sim.runaway_temperature()) {
      if (comm.root()) fmt::print(stderr, "error: {}\n", *hot);
      return kExitBlowUp;
    }
  } catch (const BlowUpError& e) {
    // Every rank raises the same error (the health check is collective); the root reports it.
    if (comm.root())
      fmt::print(stderr, "\nerror: {}\nthe last good checkpoint (if any) is kept in {}\n", e.what(), out);
    return kExitBlowUp;
  } catch (const ConfigError& e) {
    // A file of the output could not be written (collective, like the health check): the run stops
    // there, and what it had written before (checkpoints are replaced atomically) stays.
    if (comm.root())
      fmt::print(stderr, "\nerror: {}\nthe run stopped at step {}; the last good checkpoint (if any) is kept in {}\n",
                 e.what(), sim.current_step(), out);
    return kExitConfig;
  }
  return 0;
}

// `mesodpd units`: the mapping, then the requested conversions.
int units_command(const mesodpd::units::PhysicalSystem& phys, const std::vector<std::string>& to_si,
                  const std::vector<std::string>& from_si) {
  using namespace mesodpd::units;
  Mapping m;
  try {
    m = map_units(phys);
  } catch (const std::invalid_argument& e) {
    throw mesodpd::ConfigError(fmt::format("units: {}", e.what()));
  }
  fmt::print("{}", format_mapping(m));
  auto convert = [&](const std::string& arg, bool to) {
    const auto eq = arg.find('=');
    if (eq == std::string::npos) throw mesodpd::ConfigError(fmt::format("{}: expected QUANTITY=VALUE", arg));
    const std::string q = arg.substr(0, eq);
    double v = 0;
    try {
      v = std::stod(arg.substr(eq + 1));
      std::string symbol;
      for (const auto& [name, s] : quantities())
        if (name == q) symbol = s;
      if (to)
        fmt::print("{} = {} (DPD) = {:.6g} {}\n", q, v, m.to_si(v, q), symbol);
      else
        fmt::print("{} = {} {} = {:.6g} (DPD)\n", q, v, symbol, m.from_si(v, q));
    } catch (const std::invalid_argument& e) {
      throw mesodpd::ConfigError(fmt::format("{}: {}", arg, e.what()));
    }
  };
  for (const std::string& a : to_si) convert(a, true);
  for (const std::string& a : from_si) convert(a, false);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Before MPI and OpenMP start: idle threads spin briefly, then sleep (docs/performance.md).
  mesodpd::bound_openmp_spin_wait(argv);
  mesodpd::MpiSession mpi(argc, argv);
  const mesodpd::Comm world = mesodpd::Comm::world();
  CLI::App app{"mesodpd: dissipative particle dynamics engine"};
  app.set_version_flag("--version", std::string("mesodpd ") + MESODPD_VERSION);
  app.require_subcommand(1);

  std::string config, out = "out", restart;
  int threads = 0;
  std::string steps;
  bool no_progress = false;
  auto* run = app.add_subcommand("run", "run a simulation");
  run->add_option("config", config, "TOML configuration file")->required();
  run->add_option("--out", out, "output directory (default: out)");
  run->add_option("--threads", threads, "OpenMP threads (default: run.threads or all cores)");
  run->add_option("--steps", steps, "final step number, overriding run.steps");
  run->add_option("--restart", restart, "continue from this checkpoint file");
  run->add_flag("--no-progress", no_progress, "no progress bar or progress lines");

  std::string check_config;
  auto* check = app.add_subcommand("check", "validate a configuration file and exit");
  check->add_option("config", check_config, "TOML configuration file")->required();

  // Every declared key with its type, default, range and meaning: the key tables of docs/config.md.
  auto* keys = app.add_subcommand("keys", "print the declared configuration keys as the tables of docs/config.md");

  // The units mapper (include/mesodpd/units.hpp): physical liquid -> DPD parameters and SI units.
  mesodpd::units::PhysicalSystem phys;
  bool water = false;
  std::vector<std::string> to_si, from_si;
  auto* units = app.add_subcommand("units", "map a physical liquid to DPD parameters and units (docs/units.md)");
  units->add_flag("--water", water, "water at 300 K (fills what is not given; the worked example)");
  units->add_option("--nm", phys.coarse_graining, "molecules per DPD bead N_m (default 1)");
  units->add_option("--temperature", phys.temperature, "temperature in K (default 300)");
  units->add_option("--molar-mass", phys.molar_mass, "molar mass in kg/mol");
  units->add_option("--molecular-volume", phys.molecular_volume, "volume per molecule in m^3");
  units->add_option("--mass-density", phys.mass_density, "mass density in kg/m^3");
  units->add_option("--kappa-inv", phys.inverse_compressibility, "dimensionless inverse compressibility");
  units->add_option("--compressibility", phys.isothermal_compressibility, "isothermal compressibility in 1/Pa");
  units->add_option("--viscosity", phys.viscosity, "shear viscosity in Pa s");
  units->add_option("--diffusion", phys.self_diffusion, "self-diffusion of one molecule in m^2/s");
  units->add_option("--chi", phys.chi, "Flory-Huggins chi between two components (per bead)");
  units->add_option("--density", phys.dpd_density, "DPD number density rho (default 3)");
  units->add_option("--alpha", phys.alpha, "EOS coefficient (default: measured alpha(rho))");
  units->add_option("--gamma", phys.gamma, "DPD gamma for the transport estimates (default 4.5)");
  units->add_option("--dpd-viscosity", phys.dpd_viscosity, "measured viscosity of the DPD fluid (reduced)");
  units->add_option("--dpd-diffusion", phys.dpd_diffusion, "measured self-diffusion of the DPD fluid (reduced)");
  units->add_option("--time-from", phys.time_from, "auto | viscosity | diffusion | thermal (default auto)");
  units->add_option("--to-si", to_si, "QUANTITY=VALUE: a DPD value in SI (repeatable)");
  units->add_option("--from-si", from_si, "QUANTITY=VALUE: an SI value in DPD units (repeatable)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    // A bad command line is a configuration error: exit code 2 and one line, like a bad config.
    if (world.root()) fmt::print(stderr, "error: {} (see mesodpd --help)\n", e.what());
    return kExitConfig;
  }
  try {
    if (*run) {
      std::optional<std::uint64_t> steps_override;
      if (run->count("--steps") > 0) steps_override = parse_steps(steps);
      return run_command(config, out, threads, steps_override, restart, no_progress);
    }
    if (*check) {
      // The same validation as `run`, then the same reading of a data file as `run` does before its
      // first step: what passes here fails in `run` only for a reason that depends on the rank count
      // (parallel.grid against mpirun -np) or on the machine (memory, output directory).
      const mesodpd::SimulationSpec spec = mesodpd::load_config(check_config);
      const std::uint64_t n = mesodpd::check_initial_state(spec);
      fmt::print("{}: valid ({} species, {} particles{})\n", check_config, spec.species.size(), n,
                 spec.data_file.empty() ? "" : " from " + spec.data_file);
      // The settings the file changes, table by table as the keys are declared (with their units).
      fmt::print("{}", mesodpd::declared_values_summary(spec));
      // What a user should know before the run: Reynolds, Schmidt and Mach numbers, dt for the thermostat.
      fmt::print("{}", mesodpd::format_flow_numbers(mesodpd::flow_numbers(spec)));
      fmt::print("{}", mesodpd::model_numbers_summary(spec));  // the models' own (eDPD, tDPD)
      for (const std::string& w : mesodpd::spec_warnings(spec)) fmt::print(stderr, "warning: {}\n", w);
      return 0;
    }
    if (*keys) {
      fmt::print("{}", mesodpd::declared_tables_markdown());
      return 0;
    }
    if (*units) {
      if (water) {
        const mesodpd::units::PhysicalSystem w = mesodpd::units::water_300k();
        if (!phys.molar_mass && !phys.molecular_volume && !phys.mass_density) {
          phys.molar_mass = w.molar_mass;
          phys.mass_density = w.mass_density;
        }
        if (!phys.inverse_compressibility && !phys.isothermal_compressibility)
          phys.isothermal_compressibility = w.isothermal_compressibility;
        if (!phys.viscosity) phys.viscosity = w.viscosity;
        if (!phys.self_diffusion) phys.self_diffusion = w.self_diffusion;
      }
      return units_command(phys, to_si, from_si);
    }
  } catch (const mesodpd::BlowUpError& e) {
    // `check` of an initial state that a run could not integrate (a bond past its maximum length).
    if (world.root()) fmt::print(stderr, "error: {}\n", e.what());
    return kExitBlowUp;
  } catch (const mesodpd::ConfigError& e) {
    // Configuration errors are found identically on every rank (or shared by Comm::on_root).
    if (world.root()) fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  } catch (const std::exception& e) {
    // Anything else may have happened on one rank only: the others could be waiting for it.
    fmt::print(stderr, "error{}: {}\n", world.distributed() ? fmt::format(" on rank {}", world.rank()) : "", e.what());
    if (world.distributed()) world.abort(1);
    return 1;
  }
  return 0;
}
