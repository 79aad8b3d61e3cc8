// Sources and first-order reactions of the transported scalars, in boxes of space: [[source]] adds a
// constant rate to eDPD's temperature (heat) or to a tDPD concentration (solute) of the mobile particles
// inside its region; [[reaction]] converts a solute at a first-order rate, A -> B or A -> nothing
// (Li et al., J. Chem. Phys. 143, 014101 (2015), the source term Q^S of tDPD).
//
// Both act in the two half steps of the transport models (after their own half steps, so at
// AfterFirstHalf and AfterSecondHalf, each over dt/2): a source adds rate x dt/2, a reaction removes
// C_A (1 - exp(-k dt/2)) from A, exactly for that interval, and adds it to B. A reaction so never drives a
// concentration negative; a sink (a negative source) can, and the transport model's next check reports it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "engine/transported_scalars.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"

namespace mesodpd {

// One [[source]] block.
struct SourceSpec {
  std::string field;  // "temp" (eDPD) or "conc<k>" (tDPD)
  double rate = 0;
  std::optional<std::array<double, 3>> lo, hi;  // the region (default: the whole box)
  std::vector<std::string> species;              // only these species (default: every mobile one)
};

// One [[reaction]] block.
struct ReactionSpec {
  int solute = 0;   // the reactant A (1-based)
  int product = 0;  // B, or 0 for none
  double rate = 0;  // k of dC_A/dt = -k C_A
  std::optional<std::array<double, 3>> lo, hi;
};

namespace {

constexpr const char* kRegionDoc =
    "corner of the region (an axis-aligned box, lo < hi on every axis, inside [0, system.box]); default: the whole "
    "box. A particle counts while its position lies in [lo, hi).";

const keys::KeyTable<SourceSpec>& source_keys() {
  using T = SourceSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("source");
    t.string("field", &T::field,
             "The scalar the source feeds: `temp` (pair.style = \"edpd\": the rate is heat, energy per particle and "
             "unit time, so dT/dt = rate / C_v) or `conc1` .. `conc4` (pair.style = \"tdpd\": solute per particle "
             "and unit time, for a solute the run carries).")
        .required("(\"temp\" or \"conc1\", ...)");
    t.number("rate", &T::rate, keys::kFinite, "The source's rate per particle and unit time; negative for a sink.")
        .required("(per particle and unit time)");
    t.vec3("lo", &T::lo, keys::kFinite, std::string("Lower ") + kRegionDoc);
    t.vec3("hi", &T::hi, keys::kFinite, std::string("Upper ") + kRegionDoc);
    t.strings("species", &T::species, "Only particles of these species (names); default: every mobile species.");
    return t;
  }();
  return table;
}

const keys::KeyTable<ReactionSpec>& reaction_keys() {
  using T = ReactionSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("reaction");
    t.integer("solute", &T::solute, {1, kMaxScalars},
              "The reactant A (pair.style = \"tdpd\", a solute the run carries): dC_A/dt = -rate C_A.")
        .required("(the solute number, 1-based)");
    t.integer("product", &T::product, {0, kMaxScalars},
              "The product B, which gains what A loses (dC_B/dt = +rate C_A); 0 (the default) for none.");
    t.number("rate", &T::rate, keys::kPositive, "The first-order rate constant k (per unit time).")
        .required("(a first-order rate constant)");
    t.vec3("lo", &T::lo, keys::kFinite, std::string("Lower ") + kRegionDoc);
    t.vec3("hi", &T::hi, keys::kFinite, std::string("Upper ") + kRegionDoc);
    return t;
  }();
  return table;
}

// The region of a block: its corners, or the whole box.
struct Region {
  std::array<double, 3> lo{}, hi{};
  bool contains(const ParticleData& p, std::size_t i) const {
    return p.x[i] >= lo[0] && p.x[i] < hi[0] && p.y[i] >= lo[1] && p.y[i] < hi[1] && p.z[i] >= lo[2] && p.z[i] < hi[2];
  }
};

Region region_of(const std::optional<std::array<double, 3>>& lo, const std::optional<std::array<double, 3>>& hi,
                 const SimulationSpec& spec, const std::string& key) {
  Region r;
  r.hi = spec.box;
  if (lo) r.lo = *lo;
  if (hi) r.hi = *hi;
  for (std::size_t d = 0; d < 3; ++d) {
    if (!(r.lo[d] >= 0.0 && r.lo[d] < spec.box[d]))
      keys::fail(fmt::format("{}.lo[{}]", key, d), keys::show(r.lo[d]),
                 fmt::format("must lie in [0, system.box[{}] = {}): the region must be inside the box", d,
                             keys::show(spec.box[d])));
    if (!(r.hi[d] > r.lo[d] && r.hi[d] <= spec.box[d]))
      keys::fail(fmt::format("{}.hi[{}]", key, d), keys::show(r.hi[d]),
                 fmt::format("must exceed lo[{}] = {} and be at most system.box[{}] = {}", d, keys::show(r.lo[d]), d,
                             keys::show(spec.box[d])));
  }
  return r;
}

std::string_view style_of(const SimulationSpec& spec) { return pair_law(spec.pair_style).style; }

void check_sources(const std::vector<SourceSpec>& list, const SimulationSpec& spec) {
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string key = fmt::format("source[{}]", k);
    check_scalar_field(list[k].field, spec, key + ".field");
    region_of(list[k].lo, list[k].hi, spec, key);
    for (const std::string& name : list[k].species) {
      const auto it = std::find_if(spec.species.begin(), spec.species.end(), [&](const SpeciesSpec& s) { return s.name == name; });
      if (it == spec.species.end()) keys::fail(key + ".species", "\"" + name + "\"", "no [[species]] of that name");
      if (it->frozen) keys::fail(key + ".species", "\"" + name + "\"", "a frozen species is not integrated");
    }
  }
}

void check_reactions(const std::vector<ReactionSpec>& list, const SimulationSpec& spec) {
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string key = fmt::format("reaction[{}]", k);
    if (style_of(spec) != "tdpd")
      keys::fail(key + ".solute", std::to_string(list[k].solute),
                 fmt::format("[[reaction]] needs pair.style = \"tdpd\" (this run's is \"{}\")", style_of(spec)));
    if (list[k].product == list[k].solute)
      keys::fail(key + ".product", std::to_string(list[k].product), "must differ from the reactant `solute`");
    region_of(list[k].lo, list[k].hi, spec, key);
  }
}

// What the stages read: per block, the field's arrays are looked up once per half step (enabled fields
// keep their place in the list, not their storage).
struct Source {
  std::string field;
  Region region;
  std::vector<double> per_species;  // dX/dt per species: rate (conc) or rate / C_v (temp); 0 where excluded
};

struct Reaction {
  std::string from, to;  // fields; `to` empty for none
  double rate;
  Region region;
};

void apply(StepContext& ctx, const std::vector<Source>& sources, const std::vector<Reaction>& reactions) {
  ParticleData& p = ctx.particles;
  const double h = 0.5 * ctx.dt;
  for (const Source& s : sources) {
    double* v = p.doubles(s.field)->data();
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const double r = s.per_species[static_cast<std::size_t>(p.species[i])];
      if (r != 0.0 && s.region.contains(p, i)) v[i] += h * r;
    }
  }
  for (const Reaction& r : reactions) {
    double* a = p.doubles(r.from)->data();
    double* b = r.to.empty() ? nullptr : p.doubles(r.to)->data();
    const double keep = std::exp(-r.rate * h);
    for (std::size_t i = 0; i < p.n_local; ++i) {
      if (p.body[i] != 0 || !r.region.contains(p, i)) continue;
      const double gone = a[i] * (1.0 - keep);
      a[i] -= gone;
      if (b) b[i] += gone;
    }
  }
}

}  // namespace

ModelSection source_section() { return model_list_section(source_keys(), check_sources); }
ModelSection reaction_section() { return model_list_section(reaction_keys(), check_reactions); }

void install_sources(Installation& in) {
  const SimulationSpec& spec = in.spec;
  const auto* sources = spec.model<std::vector<SourceSpec>>("source");
  const auto* reactions = spec.model<std::vector<ReactionSpec>>("reaction");
  if (!sources && !reactions) return;
  const ParticleData& p = in.sim.particles();
  auto list = std::make_shared<std::vector<Source>>();
  auto react = std::make_shared<std::vector<Reaction>>();
  if (sources) {
    check_sources(*sources, spec);
    for (std::size_t k = 0; k < sources->size(); ++k) {
      const SourceSpec& s = (*sources)[k];
      require_held(p, s.field, fmt::format("source[{}].field", k), "\"" + s.field + "\"");
      Source out{s.field, region_of(s.lo, s.hi, spec, fmt::format("source[{}]", k)), {}};
      for (const SpeciesSpec& sp : spec.species) {
        const bool chosen = s.species.empty() || std::find(s.species.begin(), s.species.end(), sp.name) != s.species.end();
        const double scale = s.field == "temp" ? 1.0 / sp.own.at("cv") : 1.0;
        out.per_species.push_back(chosen && !sp.frozen ? s.rate * scale : 0.0);
      }
      list->push_back(std::move(out));
    }
  }
  if (reactions) {
    check_reactions(*reactions, spec);
    for (std::size_t k = 0; k < reactions->size(); ++k) {
      const ReactionSpec& r = (*reactions)[k];
      const std::string from = fmt::format("conc{}", r.solute), to = r.product ? fmt::format("conc{}", r.product) : "";
      require_held(p, from, fmt::format("reaction[{}].solute", k), std::to_string(r.solute));
      if (!to.empty()) require_held(p, to, fmt::format("reaction[{}].product", k), std::to_string(r.product));
      react->push_back({from, to, r.rate, region_of(r.lo, r.hi, spec, fmt::format("reaction[{}]", k))});
    }
  }
  for (StagePoint at : {StagePoint::AfterFirstHalf, StagePoint::AfterSecondHalf})
    in.stages.add(at, make_stage([list, react](StepContext& ctx) { apply(ctx, *list, *react); }));
}

}  // namespace mesodpd
