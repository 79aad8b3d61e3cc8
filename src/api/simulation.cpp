// The public facade of include/mesodpd/simulation.hpp: forwards to the engine's Simulation and copies
// its types into the public ones, so that engine headers stay private.
#include <omp.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "analysis/observers.hpp"
#include "engine/rigid_bodies.hpp"
#include "engine/simulation.hpp"
#include "io/byte_buffer.hpp"
#include "parallel/halo.hpp"
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
  run.record = options.record;
  try {
    impl_ = std::make_unique<Impl>(validated(std::move(spec)), std::move(run));
  } catch (const mesodpd::BlowUpError& e) {  // an initial state that cannot be integrated
    throw BlowUpError(e.what(), e.step(), e.particle_id());
  }
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

namespace {
// The held optional double field `name` of the engine (a model's scalar or its rate), or an error.
std::vector<double>& scalar_of(ParticleData& p, std::string_view name) {
  const std::size_t k = ParticleData::field_index(name);
  std::vector<double>* v = p.doubles(name);
  if (k == ParticleData::kFieldCount || !(ParticleData::fields()[k].flags & field::kOptional) || v == nullptr)
    throw std::invalid_argument("no particle scalar '" + std::string(name) +
                                "' in this run (scalars: temp, temp_rate with pair.style = \"edpd\"; conc1 .. conc4, "
                                "conc_rate1 .. with pair.style = \"tdpd\", as many as [tdpd] solutes)");
  return *v;
}
}  // namespace

std::span<const double> Simulation::scalar_field(std::string_view name) const {
  ParticleData& p = impl_->engine.particles();
  return owned(scalar_of(p, name), p.n_local);
}

void Simulation::set_scalar_field(std::string_view name, std::span<const double> values) {
  ParticleData& p = impl_->engine.particles();
  std::vector<double>& v = scalar_of(p, name);
  if (ParticleData::fields()[ParticleData::field_index(name)].flags & field::kForce)
    throw std::invalid_argument("particle scalar '" + std::string(name) + "' is a rate the force stage computes; set "
                                "the scalar itself");
  if (values.size() != p.n_local)
    throw std::invalid_argument("set_scalar_field('" + std::string(name) + "'): " + std::to_string(values.size()) +
                                " values for " + std::to_string(p.n_local) + " owned particles");
  std::copy(values.begin(), values.end(), v.begin());
}

namespace {
Thermo to_public(const ThermoState& s) {
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

// Rank 0's value of an analysis on every rank: `fill` writes it on the root (returns false when there
// is none), `read` rebuilds it from the bytes.
template <class T, class Fill, class Read>
std::optional<T> from_root(const Comm& comm, Fill fill, Read read) {
  std::vector<std::byte> bytes;
  if (comm.root()) {
    ByteWriter w;
    if (fill(w)) bytes = w.take();
  }
  if (comm.distributed()) comm.broadcast(bytes);
  if (bytes.empty()) return std::nullopt;
  ByteReader r(bytes, "broadcast");
  return read(r);
}
}  // namespace

Thermo Simulation::thermo() { return to_public(impl_->engine.thermo()); }

std::string Simulation::finish() { return impl_->engine.finish(); }
int Simulation::rank() const { return impl_->engine.halo().comm().rank(); }
int Simulation::ranks() const { return impl_->engine.halo().comm().size(); }

Snapshot Simulation::gather() const {
  const mesodpd::Simulation& e = impl_->engine;
  const ParticleData all = gather_by_id(e.particles(), e.halo().comm(), e.total_particles());
  Snapshot s;
  if (!e.halo().comm().root()) return s;
  const std::size_t n = all.n_local;
  auto take = [n](const auto& v) { return std::vector(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n)); };
  s.id = take(all.id);
  s.species = take(all.species);
  s.x = take(all.x);
  s.y = take(all.y);
  s.z = take(all.z);
  s.vx = take(all.vx);
  s.vy = take(all.vy);
  s.vz = take(all.vz);
  s.fx = take(all.fx);
  s.fy = take(all.fy);
  s.fz = take(all.fz);
  s.ix = take(all.ix);
  s.iy = take(all.iy);
  s.iz = take(all.iz);
  return s;
}

std::vector<Thermo> Simulation::thermo_history() const {
  std::vector<Thermo> out;
  for (const ThermoState& t : impl_->engine.observers().history()) out.push_back(to_public(t));
  return out;
}

std::optional<Profile> Simulation::profile() const {
  const Observers& o = impl_->engine.observers();
  return from_root<Profile>(
      impl_->engine.halo().comm(),
      [&](ByteWriter& w) {
        const PoiseuilleProfile* p = o.profile();
        if (!p) return false;
        const ViscosityFit fit = p->fit();
        w.put<std::int32_t>(p->flow_axis());
        w.put<std::int32_t>(p->gradient_axis());
        w.put_vector(p->z());
        w.put_vector(p->v_mean());
        w.put_vector(p->v_err());
        w.put_vector(p->v_fit());
        w.put<double>(fit.eta);
        w.put<double>(fit.eta_err);
        w.put<std::int32_t>(fit.blocks_used);
        w.put<std::uint64_t>(p->samples());
        return true;
      },
      [](ByteReader& r) {
        Profile p;
        p.flow_axis = r.get<std::int32_t>();
        p.gradient_axis = r.get<std::int32_t>();
        p.z = r.get_vector<double>();
        p.v_mean = r.get_vector<double>();
        p.v_err = r.get_vector<double>();
        p.v_fit = r.get_vector<double>();
        p.eta = r.get<double>();
        p.eta_err = r.get<double>();
        p.blocks_used = r.get<std::int32_t>();
        p.samples = r.get<std::uint64_t>();
        return p;
      });
}

std::optional<Rdf> Simulation::rdf() const {
  const Observers& o = impl_->engine.observers();
  return from_root<Rdf>(
      impl_->engine.halo().comm(),
      [&](ByteWriter& w) {
        const RadialDistribution* g = o.rdf();
        if (!g) return false;
        w.put_vector(g->r());
        w.put_vector(g->g());
        w.put<std::uint64_t>(g->samples());
        return true;
      },
      [](ByteReader& r) {
        Rdf g;
        g.r = r.get_vector<double>();
        g.g = r.get_vector<double>();
        g.samples = r.get<std::uint64_t>();
        return g;
      });
}

std::vector<Fields> Simulation::fields() const {
  std::vector<Fields> out;
  for (const BinnedFields& b : impl_->engine.observers().fields()) {
    Fields f;
    f.name = b.spec().name;
    f.bins = b.spec().bins;
    f.samples = b.samples();
    for (std::size_t c = 0; c < b.cells(); ++c) {
      const std::array<double, 3> r = b.centre(c);
      f.x.push_back(r[0]);
      f.y.push_back(r[1]);
      f.z.push_back(r[2]);
    }
    if (b.samples() > 0) {
      f.density = b.density();
      f.vx = b.velocity(0);
      f.vy = b.velocity(1);
      f.vz = b.velocity(2);
      f.temperature = b.temperature(-1);
    }
    out.push_back(std::move(f));
  }
  return out;
}

std::optional<Msd> Simulation::msd() const {
  const Observers& o = impl_->engine.observers();
  return from_root<Msd>(
      impl_->engine.halo().comm(),
      [&](ByteWriter& w) {
        const MeanSquaredDisplacement* m = o.msd();
        if (!m) return false;
        w.put_vector(m->time());
        w.put_vector(m->msd());
        w.put<double>(m->diffusion_coefficient());
        return true;
      },
      [](ByteReader& r) {
        Msd m;
        m.time = r.get_vector<double>();
        m.msd = r.get_vector<double>();
        m.diffusion = r.get<double>();
        return m;
      });
}

std::vector<Body> Simulation::bodies() const {
  std::vector<Body> out;
  const RigidBodies* rb = impl_->engine.component<RigidBodies>();
  if (!rb) return out;
  for (std::size_t k = 0; k < rb->size(); ++k) {
    const BodyState& s = rb->state(k);
    const Vec3 w = rb->omega(k), f = s.f + s.f_bounce, t = s.t + s.t_bounce;
    Body b;
    b.solid = rb->name(k);
    b.mass = rb->mass(k);
    b.particles = rb->particles(k);
    b.position = {s.x.x, s.x.y, s.x.z};
    b.orientation = {s.q.w, s.q.x, s.q.y, s.q.z};
    b.velocity = {s.v.x, s.v.y, s.v.z};
    b.angular_velocity = {w.x, w.y, w.z};
    b.force = {f.x, f.y, f.z};
    b.torque = {t.x, t.y, t.z};
    b.stresslet = rb->stresslet(k);
    out.push_back(std::move(b));
  }
  return out;
}

void Simulation::write_checkpoint(const std::filesystem::path& file) const { impl_->engine.write_checkpoint(file); }

}  // namespace mesodpd::api
