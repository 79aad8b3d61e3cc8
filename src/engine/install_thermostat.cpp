// The installer of [thermostat]: one AfterSecondHalf stage that runs the pair sweep of
// integrate/pair_thermostat.hpp on the step's complete velocities, before the health check and the
// analyses read them. The integrator's own step is Groot-Warren's with the pair law's gamma = 0, i.e.
// plain velocity Verlet for the conservative forces (lambda has no effect then).
//
// Under MPI the sweep stays serial: every rank sends its particles to rank 0, which sweeps the whole
// system exactly as one rank would (the order and the random numbers depend on positions and ids only),
// and broadcasts the new velocities by id. So a run is bit-identical on any rank count; the price is
// O(N) traffic and a serial sweep per step, which suits the small boxes transport studies use rather
// than large runs (docs/performance.md, "Pairwise thermostats").
#include <algorithm>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "integrate/thermostat_keys.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

// What travels to rank 0 per particle, and back.
struct Outgoing {
  std::uint32_t id;
  std::int32_t species;
  double r[3], v[3];
};
struct Returning {
  std::uint32_t id;
  std::uint32_t pad;
  double v[3];
};
// After the particles: the sweep's results, the same on every rank.
struct Results {
  std::uint64_t pairs;
  double virial[6];
  double temperature;
};

template <class T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v));
}

// The sweep of the whole system on rank 0 (collective).
void sweep_on_root(PairThermostat& sweep, ParticleData& all, StepContext& ctx) {
  ParticleData& p = ctx.particles;
  const Comm& comm = ctx.comm;
  std::vector<Outgoing> out(p.n_local);
  for (std::size_t i = 0; i < p.n_local; ++i)
    out[i] = {p.id[i], p.species[i], {p.x[i], p.y[i], p.z[i]}, {p.vx[i], p.vy[i], p.vz[i]}};
  const std::vector<std::byte> gathered = comm.gather(bytes_of(out));
  std::vector<std::byte> reply;
  if (comm.root()) {
    const std::size_t n = gathered.size() / sizeof(Outgoing);
    all.resize(n);
    all.n_local = n;
    for (std::size_t k = 0; k < n; ++k) {
      Outgoing o;
      std::memcpy(&o, gathered.data() + k * sizeof(Outgoing), sizeof o);
      all.id[k] = o.id;
      all.species[k] = o.species;
      all.x[k] = o.r[0], all.y[k] = o.r[1], all.z[k] = o.r[2];
      all.vx[k] = o.v[0], all.vy[k] = o.v[1], all.vz[k] = o.v[2];
    }
    sweep.sweep(all, ctx.box, ctx.species_mass, ctx.step, ctx.dt);
    std::vector<Returning> back(n);
    for (std::size_t k = 0; k < n; ++k) back[k] = {all.id[k], 0, {all.vx[k], all.vy[k], all.vz[k]}};
    std::sort(back.begin(), back.end(), [](const Returning& a, const Returning& b) { return a.id < b.id; });
    Results res{sweep.last_pairs(), {}, sweep.last_temperature()};
    std::copy(sweep.last_virial().begin(), sweep.last_virial().end(), res.virial);
    reply.resize(n * sizeof(Returning) + sizeof(Results));
    std::memcpy(reply.data(), back.data(), n * sizeof(Returning));
    std::memcpy(reply.data() + n * sizeof(Returning), &res, sizeof res);
  }
  comm.broadcast(reply);
  const std::size_t n = (reply.size() - sizeof(Results)) / sizeof(Returning);
  Results res;
  std::memcpy(&res, reply.data() + n * sizeof(Returning), sizeof res);
  std::array<double, 6> virial;
  std::copy(res.virial, res.virial + 6, virial.begin());
  sweep.adopt(res.pairs, virial, res.temperature);
  // Each rank's particles take their new velocities, found by id in the sorted list.
  const auto* back = reinterpret_cast<const Returning*>(reply.data());
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const Returning* r =
        std::lower_bound(back, back + n, p.id[i], [](const Returning& a, std::uint32_t id) { return a.id < id; });
    if (r == back + n || r->id != p.id[i])
      throw std::logic_error("[thermostat]: particle id " + std::to_string(p.id[i]) + " missing from rank 0's sweep");
    p.vx[i] = r->v[0];
    p.vy[i] = r->v[1];
    p.vz[i] = r->v[2];
  }
}

}  // namespace

void install_thermostat(Installation& in) {
  const ThermostatSpec* t = in.spec.model<ThermostatSpec>("thermostat");
  if (!t) return;
  check_thermostat(*t, in.spec);  // again, for specs built in code
  // A law with particle temperatures (eDPD) conserves energy with its own friction and heat: a sweep that
  // changes the kinetic energy behind its back would break that.
  if (pair_law(in.spec.pair_style).style == "edpd")
    throw SpecError("pair.style", "\"" + std::string(pair_law(in.spec.pair_style).style) + "\"",
                    "[thermostat] is not supported with a law that carries particle temperatures (its energy "
                    "balance has no place for the thermostat's heat)");
  auto sweep = std::make_shared<PairThermostat>(thermostat_params(*t, in.spec));
  in.components.add(sweep);
  auto all = std::make_shared<ParticleData>();  // rank 0's copy of the whole system under MPI
  in.stages.add(StagePoint::AfterSecondHalf, make_stage([sweep, all](StepContext& ctx) {
                  if (ctx.comm.distributed())
                    sweep_on_root(*sweep, *all, ctx);
                  else
                    sweep->sweep(ctx.particles, ctx.box, ctx.species_mass, ctx.step, ctx.dt);
                  // The impulses carry momentum between pairs: part of the stress (all of the friction's
                  // share), read by thermo, Lees-Edwards and Green-Kubo at EndOfStep.
                  if (ctx.pair_sums)
                    for (std::size_t c = 0; c < 6; ++c) ctx.pair_sums->virial[c] += sweep->last_virial()[c];
                }));
}

}  // namespace mesodpd
