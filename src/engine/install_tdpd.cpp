// The installer of transport DPD (physics/tdpd_pair.hpp, pair.style = "tdpd"): the particles' solute
// concentrations, their integration, the [tdpd] section and the thermo columns.
//
// The concentrations follow the velocity's modified velocity-Verlet step, as eDPD's temperatures do (and
// as LAMMPS's fix mvv/tdpd): C += dt/2 dC/dt with the rate of the last force evaluation after the
// velocities' first half, the new rates at the new positions, then C += dt/2 dC/dt again after the
// second half. The rates live in p.conc_rate<k> (kForce, checkpointed), so a restart continues
// bit-identically. Frozen particles keep their concentrations: a solute wall (species key
// `solute_wall = 1`) is held at its values, an impermeable one exchanges nothing (the law's pairs).
//
// A concentration is never clipped: one that becomes negative (a time step too large for the Fick flux,
// or a random flux too strong for a small concentration) stops the run naming the step, the particle
// and the solute, or with [tdpd] negative = "count" is counted and reported.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/blow_up_error.hpp"
#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "engine/transported_scalars.hpp"
#include "mesodpd/config_error.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"
#include "parallel/comm.hpp"
#include "physics/tdpd_pair.hpp"

namespace mesodpd {

enum class NegativeConcentration { Stop, Count };

// [tdpd]: how many solutes the run carries and what a negative concentration does.
struct TdpdSpec {
  int solutes = 1;
  NegativeConcentration negative = NegativeConcentration::Stop;
};

namespace {

__extension__ using Int128 = __int128;
constexpr double kAmountScale = 1099511627776.0;  // 2^40: the fixed point of the solute sums

const keys::KeyTable<TdpdSpec>& tdpd_keys() {
  using T = TdpdSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("tdpd");
    t.integer("solutes", &T::solutes, {1, kMaxSolutes},
              "Number of solute concentrations each particle carries with `pair.style = \"tdpd\"` (fields `conc1` .. "
              "`conc<N>`; pair keys `kappa<k>`, `epsilon<k>`, `sc<k>` and species keys `conc<k>` for k <= N). Without "
              "a [tdpd] table a tdpd run carries one solute.");
    t.choice("negative", &T::negative, {{"stop", NegativeConcentration::Stop}, {"count", NegativeConcentration::Count}},
             "What a concentration that becomes negative does (it is never clipped): `stop` ends the run naming "
             "the step, the particle and the solute (exit code 3, the last checkpoint kept); `count` goes on and "
             "reports how many particle-steps had one (thermo column `conc_negative` and the end-of-run summary).");
    return t;
  }();
  return table;
}

// The checks of a tdpd spec that the ranges cannot make: keys of solutes the run does not carry, the
// section without the style.
void check_tdpd(const TdpdSpec& t, const SimulationSpec& spec) {
  if (pair_law(spec.pair_style).style != TdpdLaw::kStyle)
    keys::fail("tdpd.solutes", std::to_string(t.solutes),
               "[tdpd] needs pair.style = \"tdpd\" (this run's is \"" + std::string(pair_law(spec.pair_style).style) +
                   "\")");
  for (int k = t.solutes + 1; k <= kMaxSolutes; ++k) {
    for (const char* key : {"kappa", "epsilon"})
      for (const PairSpec& ps : spec.pairs)
        if (const double v = ps.value(fmt::format("{}{}", key, k)); v != 0.0)
          keys::fail(fmt::format("pair.{}{}", key, k), keys::show(v),
                     fmt::format("solute {} is not carried: [tdpd] solutes = {} (species pair {}-{})", k, t.solutes,
                                 spec.species.at(static_cast<std::size_t>(ps.i)).name,
                                 spec.species.at(static_cast<std::size_t>(ps.j)).name));
    for (std::size_t s = 0; s < spec.species.size(); ++s)
      if (const auto it = spec.species[s].own.find(fmt::format("conc{}", k));
          it != spec.species[s].own.end() && it->second != 0.0)
        keys::fail(fmt::format("species[{}].conc{}", s, k), keys::show(it->second),
                   fmt::format("solute {} is not carried: [tdpd] solutes = {}", k, t.solutes));
  }
}

// The per-species values the integration reads.
struct TdpdState {
  int solutes = 1;
  NegativeConcentration negative = NegativeConcentration::Stop;
  std::vector<std::array<double, kMaxSolutes>> start;  // starting (a wall's: held) concentrations
  std::vector<std::uint8_t> frozen;
  std::uint64_t negatives = 0;  // particle-steps with a negative concentration (negative = "count")
  std::uint64_t first_step = 0;
  std::uint32_t first_id = 0;
  int first_solute = 0;
};

double* conc(ParticleData& p, int k) { return p.doubles(TdpdLaw::kScalarFields[static_cast<std::size_t>(k)])->data(); }
double* rate(ParticleData& p, int k) { return p.doubles(TdpdLaw::kScalarRates[static_cast<std::size_t>(k)])->data(); }

// C += dt/2 dC/dt for the mobile local particles, then the negatives: the smallest id over all ranks
// (with its solute) stops the run, or the count grows.
void half_step(StepContext& ctx, TdpdState& s) {
  ParticleData& p = ctx.particles;
  const double h = 0.5 * ctx.dt;
  std::uint64_t bad = std::numeric_limits<std::uint64_t>::max();  // id * 8 + solute of the first negative
  double bad_c = 0;
  std::uint64_t count = 0;
  for (int k = 0; k < s.solutes; ++k) {
    double* c = conc(p, k);
    const double* r = rate(p, k);
    for (std::size_t i = 0; i < p.n_local; ++i) {
      if (s.frozen[static_cast<std::size_t>(p.species[i])]) continue;
      c[i] += h * r[i];
      if (!(c[i] >= 0) || !std::isfinite(c[i])) {
        ++count;
        const std::uint64_t key = std::uint64_t{p.id[i]} * 8 + static_cast<std::uint64_t>(k);
        if (key < bad) {
          bad = key;
          bad_c = c[i];
        }
      }
    }
  }
  const bool distributed = ctx.comm.distributed();
  const std::uint64_t first = distributed ? ctx.comm.min(bad) : bad;
  if (first == std::numeric_limits<std::uint64_t>::max()) return;
  const auto id = static_cast<std::uint32_t>(first / 8);
  const int solute = static_cast<int>(first % 8) + 1;
  if (s.negative == NegativeConcentration::Stop)
    throw BlowUpError(ctx.step, id,
                      fmt::format("step {}: the concentration of solute {} on particle {} is {} (negative; tDPD never "
                                  "clips it: a time step too large for kappa, or a random flux epsilon too strong; "
                                  "[tdpd] negative = \"count\" reports instead of stopping)",
                                  ctx.step, solute, id, first == bad ? fmt::format("{}", bad_c) : std::string("negative")));
  if (s.negatives == 0) {
    s.first_step = ctx.step;
    s.first_id = id;
    s.first_solute = solute;
  }
  std::uint64_t total[1] = {count};
  if (distributed) ctx.comm.sum(std::span<std::uint64_t>(total, 1));
  s.negatives += total[0];
}

}  // namespace

ModelSection tdpd_section() { return model_section(tdpd_keys(), check_tdpd); }

int tdpd_solutes(const SimulationSpec& spec) {
  if (pair_law(spec.pair_style).style != TdpdLaw::kStyle) return 0;
  const TdpdSpec* t = spec.model<TdpdSpec>("tdpd");
  return t ? t->solutes : 1;
}

std::string tdpd_numbers(const SimulationSpec& spec) {
  if (pair_law(spec.pair_style).style != TdpdLaw::kStyle || spec.species.empty()) return "";
  const TdpdSpec* t = spec.model<TdpdSpec>("tdpd");
  const int solutes = t ? t->solutes : 1;
  const PairSpec& p = spec.pair(0, 0);
  const double rcc = p.value("rcc") > 0 ? p.value("rcc") : p.rc;
  std::string out = "tDPD (species " + spec.species.front().name + "):\n";
  for (int k = 1; k <= solutes; ++k)
    out += scalar_numbers_line(
        spec, fmt::format("solute {} (kappa = {}, r_cc = {})", k, p.value(fmt::format("kappa{}", k)), rcc),
        field_exchange_diffusivity(spec, fmt::format("conc{}", k)), "Schmidt number");
  return out;
}

void install_tdpd(Installation& in) {
  const SimulationSpec& spec = in.spec;
  if (pair_law(spec.pair_style).style != TdpdLaw::kStyle) return;
  const TdpdSpec* section = spec.model<TdpdSpec>("tdpd");
  const TdpdSpec t = section ? *section : TdpdSpec{};
  check_tdpd(t, spec);  // again, for specs built in code and for a run without [tdpd]
  if (spec.bond_exclusion != BondExclusion::None)
    throw ConfigError("bonds.exclude: bonded exclusions are not yet supported with pair.style = \"tdpd\" (they would "
                      "remove the pair's force but not its solute flux)",
                      "bonds.exclude");
  if (spec.integrator != IntegratorKind::GrootWarren)
    throw ConfigError("integrator.type: pair.style = \"tdpd\" integrates the concentrations with the velocity-Verlet "
                      "step; use integrator.type = \"groot-warren\"",
                      "integrator.type");
  auto s = std::make_shared<TdpdState>();
  s->solutes = t.solutes;
  s->negative = t.negative;
  for (const SpeciesSpec& sp : spec.species) {
    std::array<double, kMaxSolutes> c{};
    for (int k = 0; k < kMaxSolutes; ++k) c[static_cast<std::size_t>(k)] = sp.own.at(fmt::format("conc{}", k + 1));
    s->start.push_back(c);
    s->frozen.push_back(sp.frozen ? 1 : 0);
  }
  ParticleData& p = in.sim.particles();
  for (int k = 0; k < t.solutes; ++k) {
    const std::string_view field = TdpdLaw::kScalarFields[static_cast<std::size_t>(k)];
    const std::string_view rates = TdpdLaw::kScalarRates[static_cast<std::size_t>(k)];
    if (in.restarted) {
      if (!p.enabled(field) || !p.enabled(rates))
        throw ConfigError(fmt::format("tdpd.solutes: {} solutes, but the checkpoint holds no concentrations of solute "
                                      "{} (it continues only a tdpd run with as many solutes)",
                                      t.solutes, k + 1),
                          "tdpd.solutes");
      continue;
    }
    p.enable(rates);
    if (p.enabled(field)) continue;  // from a data file (atom style tdpd; engine/initial_state.cpp checked it)
    p.enable(field);
    double* c = conc(p, k);
    for (std::size_t i = 0; i < p.n_local; ++i)
      c[i] = s->start[static_cast<std::size_t>(p.species[i])][static_cast<std::size_t>(k)];
  }
  if (in.restarted && t.solutes < kMaxSolutes &&
      p.enabled(TdpdLaw::kScalarFields[static_cast<std::size_t>(t.solutes)]))
    throw ConfigError(fmt::format("tdpd.solutes: {} solutes, but the checkpoint holds more", t.solutes), "tdpd.solutes");
  in.stages.add(StagePoint::AfterFirstHalf, make_stage([s](StepContext& ctx) { half_step(ctx, *s); }));
  in.stages.add(StagePoint::AfterSecondHalf, make_stage([s](StepContext& ctx) { half_step(ctx, *s); }));
  // The amount of each solute in the fluid (mobile particles), in 128-bit fixed point: the same on any
  // rank count and storage order. The pair fluxes conserve it up to what the walls exchange.
  auto amounts = std::make_shared<std::array<double, kMaxSolutes>>();
  for (int k = 0; k < t.solutes; ++k)
    in.thermo_columns.push_back({fmt::format("solute{}", k + 1), [s, amounts, k](const StepContext& ctx) {
                                   if (k == 0) {
                                     ParticleData& q = ctx.particles;
                                     Int128 acc[kMaxSolutes] = {0, 0, 0, 0};
                                     for (int c = 0; c < s->solutes; ++c) {
                                       const double* v = conc(q, c);
                                       for (std::size_t i = 0; i < q.n_local; ++i)
                                         if (!s->frozen[static_cast<std::size_t>(q.species[i])])
                                           acc[c] += static_cast<Int128>(v[i] * kAmountScale);
                                     }
                                     ctx.comm.sum(std::span<Int128>(acc, static_cast<std::size_t>(s->solutes)));
                                     for (int c = 0; c < s->solutes; ++c)
                                       (*amounts)[static_cast<std::size_t>(c)] = static_cast<double>(acc[c]) / kAmountScale;
                                   }
                                   return (*amounts)[static_cast<std::size_t>(k)];
                                 }});
  if (t.negative == NegativeConcentration::Count) {
    // The count and its first event travel in checkpoints (the same on every rank: the totals are reduced).
    in.sections.push_back({"tdpd_negatives",
                           [s](ByteWriter& w) {
                             w.put<std::uint64_t>(s->negatives);
                             w.put<std::uint64_t>(s->first_step);
                             w.put<std::uint32_t>(s->first_id);
                             w.put<std::int32_t>(s->first_solute);
                           },
                           [s](ByteReader& r, const std::string&) {
                             s->negatives = r.get<std::uint64_t>();
                             s->first_step = r.get<std::uint64_t>();
                             s->first_id = r.get<std::uint32_t>();
                             s->first_solute = r.get<std::int32_t>();
                           }});
    in.thermo_columns.push_back({"conc_negative", [s](const StepContext&) { return static_cast<double>(s->negatives); }});
    in.summaries.push_back([s](const StepContext&) -> std::string {
      if (s->negatives == 0) return "tdpd: no concentration became negative\n";
      return fmt::format("tdpd: {} particle-steps had a negative concentration (not clipped); the first: solute {} of "
                         "particle {} at step {}\n",
                         s->negatives, s->first_solute, s->first_id, s->first_step);
    });
  }
}

}  // namespace mesodpd
