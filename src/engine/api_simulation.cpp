// The public facade of include/mesodpd/simulation.hpp: forwards to the engine's Simulation and copies
// its types into the public ones, so that engine headers stay private.
#include <omp.h>

#include "engine/simulation.hpp"
#include "mesodpd/simulation.hpp"

namespace mesodpd::api {

struct Simulation::Impl {
  mesodpd::Simulation engine;
  Impl(SimulationSpec spec, RunOptions options) : engine(std::move(spec), std::move(options)) {}
};

namespace {
SimulationSpec validated(SimulationSpec spec) {
  validate(spec);
  if (spec.threads > 0) omp_set_num_threads(spec.threads);
  return spec;
}

template <class T>
std::span<const T> owned(const std::vector<T>& v, std::size_t n) {
  return std::span<const T>(v.data(), n);
}
}  // namespace

Simulation::Simulation(SimulationSpec spec, Options options) {
  RunOptions run;
  run.out_dir = std::move(options.output_dir);
  run.restart = std::move(options.restart);
  run.steps = options.final_step;
  run.progress = options.progress;
  impl_ = std::make_unique<Impl>(validated(std::move(spec)), std::move(run));
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

void Simulation::step(std::uint64_t steps) {
  try {
    for (std::uint64_t k = 0; k < steps; ++k) impl_->engine.step();
  } catch (const mesodpd::BlowUpError& e) {
    throw BlowUpError(e.what(), e.step(), e.particle_id());
  }
}

std::string Simulation::run() {
  try {
    return impl_->engine.run();
  } catch (const mesodpd::BlowUpError& e) {
    throw BlowUpError(e.what(), e.step(), e.particle_id());
  }
}

const SimulationSpec& Simulation::spec() const { return impl_->engine.spec(); }
std::uint64_t Simulation::current_step() const { return impl_->engine.current_step(); }
std::uint64_t Simulation::final_step() const { return impl_->engine.final_step(); }
double Simulation::time() const { return static_cast<double>(current_step()) * spec().dt; }
std::uint64_t Simulation::total_particles() const { return impl_->engine.total_particles(); }

std::array<double, 3> Simulation::box() const {
  const Box& b = impl_->engine.box();
  return {b.len.x, b.len.y, b.len.z};
}

Particles Simulation::particles() const {
  const ParticleData& p = impl_->engine.particles();
  const std::size_t n = p.n_local;
  return Particles{owned(p.id, n),  owned(p.species, n), owned(p.x, n),  owned(p.y, n),  owned(p.z, n),
                   owned(p.vx, n), owned(p.vy, n),      owned(p.vz, n), owned(p.fx, n), owned(p.fy, n),
                   owned(p.fz, n), owned(p.ix, n),      owned(p.iy, n), owned(p.iz, n)};
}

Thermo Simulation::thermo() {
  const ThermoState s = impl_->engine.thermo();
  Thermo t;
  t.step = s.step;
  t.time = s.time;
  t.temperature = s.temperature;
  t.temperature_transverse = s.temperature_transverse;
  t.pressure = s.pressure;
  t.pressure_tensor = s.p_tensor;
  t.pressure_conservative = s.pressure_conservative;
  t.momentum = s.momentum;
  t.potential_energy = s.potential_energy;
  t.kinetic_energy = s.kinetic_energy;
  return t;
}

void Simulation::write_checkpoint(const std::filesystem::path& file) const { impl_->engine.write_checkpoint(file); }

}  // namespace mesodpd::api
