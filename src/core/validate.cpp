// validate(spec): ranges, cross-checks and derived defaults of a SimulationSpec, one function per
// section of the schema (docs/config.md), applied in the order of kSections below.
#include "mesodpd/validate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string_view>
#include <vector>

#include "io/frame.hpp"

namespace mesodpd {

SpecError::SpecError(std::string key, std::string value, std::string why)
    : ConfigError(value.empty() ? fmt::format("{}: {}", key, why) : fmt::format("{} = {}: {}", key, value, why), key),
      value_(std::move(value)),
      why_(std::move(why)) {}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// Values as text, and the checks every section uses

std::string show(double v) { return fmt::format("{}", v); }
std::string show(const std::string& v) { return fmt::format("\"{}\"", v); }
std::string show(const std::vector<std::string>& v) {
  std::string out = "[";
  for (std::size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + show(v[k]);
  return out + "]";
}
std::string show_axis(int axis) { return axis >= 0 && axis < 3 ? fmt::format("\"{}\"", "xyz"[axis]) : show(axis); }

std::string quoted_list(const std::vector<std::string_view>& items) {
  std::string out;
  for (const std::string_view item : items) out += fmt::format("{}\"{}\"", out.empty() ? "" : ", ", item);
  return out;
}

[[noreturn]] void fail(const std::string& key, std::string value, std::string why) {
  throw SpecError(key, std::move(value), std::move(why));
}

// An allowed interval for a real value; non-finite values are always outside.
struct Range {
  double lo = -kInf, hi = kInf;
  bool lo_closed = true, hi_closed = true;

  bool contains(double v) const {
    return std::isfinite(v) && (lo_closed ? v >= lo : v > lo) && (hi_closed ? v <= hi : v < hi);
  }
  std::string text() const {
    if (lo == -kInf && hi == kInf) return "must be a finite number";
    if (hi == kInf) return fmt::format("must be {} {}", lo_closed ? ">=" : ">", lo);
    return fmt::format("must be in {}{}, {}{}", lo_closed ? '[' : '(', lo, hi, hi_closed ? ']' : ')');
  }
};
constexpr Range kPositive{0.0, kInf, false, true};
constexpr Range kNonNegative{0.0, kInf, true, true};
constexpr Range kFinite{};
constexpr Range kCutoff{0.0, 10.0, false, true};  // rc, rd and s share (0, 10]

void check(const std::string& key, double v, Range r) {
  if (!r.contains(v)) fail(key, show(v), r.text());
}
void check(const std::string& key, const std::optional<double>& v, Range r) {
  if (v) check(key, *v, r);
}
void check(const std::string& key, const std::array<double, 3>& v, Range r) {
  for (std::size_t d = 0; d < 3; ++d) check(fmt::format("{}[{}]", key, d), v[d], r);
}
template <class Int>
void check_at_least(const std::string& key, Int v, long long lo) {
  if (static_cast<long long>(v) < lo) fail(key, fmt::format("{}", v), fmt::format("must be an integer >= {}", lo));
}
template <class Int>
void check_between(const std::string& key, Int v, long long lo, long long hi) {
  check_at_least(key, v, lo);
  if (static_cast<long long>(v) > hi) fail(key, fmt::format("{}", v), fmt::format("must be an integer <= {}", hi));
}

std::string species_key(std::size_t k, std::string_view field) { return fmt::format("species[{}].{}", k, field); }

// The largest interaction range of any pair (the pairs are resolved by then).
double largest_cutoff(const SimulationSpec& spec) {
  double cutoff = 0.0;
  for (const PairSpec& p : spec.pairs) cutoff = std::max({cutoff, p.rc, p.rd});
  return cutoff;
}

// ---------------------------------------------------------------------------------------------
// Sections

void validate_system(SimulationSpec& spec) {
  check("system.box", spec.box, kPositive);
  const auto& per = spec.periodic;
  // The engine handles bounded axes (docs/architecture.md, "Boundaries"), but until walls exist nothing
  // would keep the particles in.
  if (!(per[0] && per[1] && per[2]))
    fail("system.periodic", fmt::format("[{}, {}, {}]", per[0], per[1], per[2]),
         "a bounded axis (false) needs walls to close it, which are not implemented yet; use [true, true, true]");
  check("system.kT", spec.kT, kPositive);
}

void validate_init(SimulationSpec& spec) {
  const bool has_data = !spec.data_file.empty();
  if (has_data) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(spec.data_file, ec))
      fail("init.lammps_data", show(spec.data_file), fmt::format("no such file '{}'", spec.data_file));
  }
  if (spec.velocities == VelocityInit::File && !has_data)
    fail("init.velocities", "\"file\"", "needs init.lammps_data to read velocities from");
  spec.init_velocities = spec.velocities == VelocityInit::Maxwell;
}

bool valid_species_name(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

void validate_species(SimulationSpec& spec) {
  if (spec.species.empty()) fail("species", "", "at least one [[species]] block is needed");
  const Mixing mixing = spec.pair_section.mixing;
  const bool from_data = !spec.data_file.empty();
  const double volume = spec.box[0] * spec.box[1] * spec.box[2];
  for (std::size_t k = 0; k < spec.species.size(); ++k) {
    SpeciesSpec& sp = spec.species[k];
    if (!valid_species_name(sp.name))
      fail(species_key(k, "name"), show(sp.name), "must be non-empty and use only letters, digits and '_'");
    for (std::size_t prev = 0; prev < k; ++prev)
      if (spec.species[prev].name == sp.name)
        fail(species_key(k, "name"), show(sp.name), fmt::format("duplicate species name (also species[{}].name)", prev));
    check(species_key(k, "mass"), sp.mass, kPositive);
    check(species_key(k, "a"), sp.a, kNonNegative);
    if (mixing == Mixing::Geometric && !sp.a)
      fail(species_key(k, "a"), "", "missing: pair.mixing = \"geometric\" needs a for every species");
    if (mixing == Mixing::Explicit && sp.a)
      fail(species_key(k, "a"), show(*sp.a),
           "only used with pair.mixing = \"geometric\"; use pair.a or [[pair.override]] instead");
    check(species_key(k, "body_force"), sp.body_force, kFinite);
    check(species_key(k, "density"), sp.density, kPositive);
    if (from_data) {
      // Positions, and so counts, come from the data file.
      if (sp.density)
        fail(species_key(k, "density"), show(*sp.density), "not allowed with init.lammps_data (particles come from the data file)");
      if (sp.count != 0)
        fail(species_key(k, "count"), fmt::format("{}", sp.count), "not allowed with init.lammps_data (particles come from the data file)");
    } else if (sp.density) {
      const double n = std::round(*sp.density * volume);
      if (n > 1.0e15) fail(species_key(k, "density"), show(*sp.density), fmt::format("gives {:.3g} particles in the box; too many", n));
      // The density decides: a count left by an earlier validate() follows a changed box. (A file that
      // sets both keys is refused by the reader, which sees which keys are written.)
      sp.count = static_cast<std::uint64_t>(n);
    }
  }
}

void validate_pair_params(const std::string& prefix, const PairParams& p) {
  check(prefix + ".a", p.a, kNonNegative);
  check(prefix + ".gamma", p.gamma, kNonNegative);
  check(prefix + ".sigma", p.sigma, kNonNegative);
  check(prefix + ".rc", p.rc, kCutoff);
  check(prefix + ".rd", p.rd, kCutoff);
  check(prefix + ".s", p.s, kCutoff);
}

// Resolves every unordered species pair: override > (geometric mixing for a | [pair]) > default.
void validate_pairs(SimulationSpec& spec) {
  const PairSection& sec = spec.pair_section;
  validate_pair_params("pair", sec.params);
  if (spec.pair_style == PairStyle::Soft) {
    // The soft law reads a (its amplitude A) and rc only: a thermostat key would be silently ignored.
    auto refuse_thermostat_keys = [](const std::string& prefix, const PairParams& p) {
      for (const auto& [name, value] : {std::pair{"gamma", p.gamma}, {"sigma", p.sigma}, {"rd", p.rd}, {"s", p.s}})
        if (value)
          fail(prefix + "." + name, show(*value),
               "not used with pair.style = \"soft\" (a conservative law without dissipative or random force)");
    };
    refuse_thermostat_keys("pair", sec.params);
    for (std::size_t k = 0; k < sec.overrides.size(); ++k)
      refuse_thermostat_keys(fmt::format("pair.override[{}]", k), sec.overrides[k].params);
  }
  if (sec.mixing == Mixing::Geometric && sec.params.a)
    fail("pair.a", show(*sec.params.a), "not used with pair.mixing = \"geometric\" (a_ij = sqrt(a_i a_j) from species[].a)");

  const std::size_t n = spec.species.size();
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> override_of(n * n, kNone);  // override index for (i, j), i <= j
  std::vector<std::string_view> names;
  for (const SpeciesSpec& sp : spec.species) names.push_back(sp.name);
  for (std::size_t k = 0; k < sec.overrides.size(); ++k) {
    const PairOverride& o = sec.overrides[k];
    const std::string key = fmt::format("pair.override[{}]", k);
    if (o.species.size() != 2) fail(key + ".species", show(o.species), "must name exactly two species");
    std::array<std::size_t, 2> id{};
    for (std::size_t e = 0; e < 2; ++e) {
      const auto it = std::find(names.begin(), names.end(), o.species[e]);
      if (it == names.end())
        fail(key + ".species", show(o.species),
             fmt::format("unknown species \"{}\" (defined: {})", o.species[e], quoted_list(names)));
      id[e] = static_cast<std::size_t>(it - names.begin());
    }
    std::size_t& slot = override_of[std::min(id[0], id[1]) * n + std::max(id[0], id[1])];
    if (slot != kNone) fail(key + ".species", show(o.species), fmt::format("this pair is already set by pair.override[{}]", slot));
    slot = k;
    validate_pair_params(key, o.params);
  }

  spec.pairs.clear();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i; j < n; ++j) {
      const std::size_t k = override_of[i * n + j];
      const PairParams* ov = k != kNone ? &sec.overrides[k].params : nullptr;
      const std::string ov_key = fmt::format("pair.override[{}]", k);
      const auto pick = [&](std::optional<double> PairParams::*member) {
        return ov && (ov->*member) ? ov->*member : sec.params.*member;
      };
      PairSpec p;
      p.i = static_cast<int>(i);
      p.j = static_cast<int>(j);
      if (ov && ov->a) {
        p.a = *ov->a;
      } else if (sec.mixing == Mixing::Geometric) {
        p.a = std::sqrt(*spec.species[i].a * *spec.species[j].a);  // seed 002 Eq. 4
      } else {
        p.a = sec.params.a.value_or(25.0);
      }
      p.gamma = pick(&PairParams::gamma).value_or(4.5);
      p.rc = pick(&PairParams::rc).value_or(1.0);
      p.rd = pick(&PairParams::rd).value_or(p.rc);  // rd follows this pair's rc unless set
      p.s = pick(&PairParams::s).value_or(2.0);

      // sigma is not independent: fluctuation-dissipation fixes sigma^2 = 2 gamma kT (seed 000 Eq. 7).
      if (const auto sigma = pick(&PairParams::sigma)) {
        const std::string sigma_key = (ov && ov->sigma ? ov_key : std::string("pair")) + ".sigma";
        const std::string gamma_key = (ov && ov->gamma ? ov_key : std::string("pair")) + ".gamma";
        const double lhs = *sigma * *sigma, rhs = 2.0 * p.gamma * spec.kT;
        if (std::abs(lhs - rhs) > 1e-6 * std::max(lhs, rhs))
          fail(sigma_key, show(*sigma),
               fmt::format("inconsistent with {} = {} and system.kT = {} for species pair ({}, {}): "
                           "sigma^2 = 2 gamma kT requires sigma = {} (seed 000 Eq. 7)",
                           gamma_key, p.gamma, spec.kT, names[i], names[j], std::sqrt(rhs)));
      }
      spec.pairs.push_back(p);
    }
  }
}

void validate_integrator(SimulationSpec& spec) {
  check("integrator.dt", spec.dt, Range{0.0, 0.5, false, true});
  check("integrator.lambda", spec.lambda, Range{0.0, 1.0, true, true});
}

void validate_run(SimulationSpec& spec) {
  check("run.max_velocity", spec.max_velocity, kPositive);
  check_between("run.threads", spec.threads, 0, kMaxThreads);
}

void validate_neighbor(SimulationSpec& spec) { check("neighbor.skin", spec.skin, Range{0.0, 2.0, true, true}); }

void validate_parallel(SimulationSpec& spec) {
  for (std::size_t d = 0; d < 3; ++d) check_between(fmt::format("parallel.grid[{}]", d), spec.parallel_grid[d], 0, 65536);
}

void validate_output(SimulationSpec& spec) {
  check_at_least("output.thermo_every", spec.thermo_every, 1);
  DumpSpec& d = spec.dump;
  if (!d.enabled) return;
  check_at_least("output.dump.every", d.every, 1);
  // The six standard selections and the extra fields the particle field list offers to frames.
  const std::vector<std::string>& names = trajectory_field_names();
  const std::vector<std::string_view> kFields(names.begin(), names.end());
  if (d.fields.empty()) fail("output.dump.fields", "[]", fmt::format("must list at least one of {}", quoted_list(kFields)));
  for (std::size_t k = 0; k < d.fields.size(); ++k) {
    const std::string& f = d.fields[k];
    if (std::find(kFields.begin(), kFields.end(), f) == kFields.end())
      fail("output.dump.fields", show(d.fields), fmt::format("unknown field \"{}\" (allowed: {})", f, quoted_list(kFields)));
    if (std::find(d.fields.begin(), d.fields.begin() + static_cast<std::ptrdiff_t>(k), f) !=
        d.fields.begin() + static_cast<std::ptrdiff_t>(k))
      fail("output.dump.fields", show(d.fields), fmt::format("field \"{}\" is listed twice", f));
  }
  if (d.file.empty()) d.file = d.format == DumpFormat::Gsd ? "trajectory.gsd" : "trajectory.lammpstrj";
}

void validate_poiseuille(SimulationSpec& spec) {
  const PoiseuilleSpec& p = spec.poiseuille;
  if (!p.enabled) return;
  check("poiseuille.force", p.force, kFinite);
  if (p.force == 0.0) fail("poiseuille.force", show(p.force), "must be non-zero");
  for (const auto& [key, axis] : {std::pair{"poiseuille.flow_axis", p.flow_axis}, {"poiseuille.gradient_axis", p.gradient_axis}})
    if (axis < 0 || axis > 2) fail(key, show_axis(axis), "must be one of \"x\", \"y\", \"z\" (0, 1, 2)");
  if (p.flow_axis == p.gradient_axis)
    fail("poiseuille.gradient_axis", show_axis(p.gradient_axis),
         fmt::format("must differ from poiseuille.flow_axis ({})", show_axis(p.flow_axis)));
  check_at_least("poiseuille.bins", p.bins, 4);
  if (p.bins % 2 != 0) fail("poiseuille.bins", fmt::format("{}", p.bins), "must be even (the two flow halves get equal bins)");
  check_at_least("poiseuille.every", p.every, 1);
  check_at_least("poiseuille.blocks", p.blocks, 2);
}

void validate_analysis(SimulationSpec& spec) {
  if (spec.rdf.enabled) {
    check_at_least("analysis.rdf.bins", spec.rdf.bins, 1);
    check("analysis.rdf.rmax", spec.rdf.rmax, kPositive);
    const double half_box = 0.5 * std::min({spec.box[0], spec.box[1], spec.box[2]});
    if (!(spec.rdf.rmax < half_box))
      fail("analysis.rdf.rmax", show(spec.rdf.rmax), fmt::format("must be < half the smallest box length ({})", half_box));
    check_at_least("analysis.rdf.every", spec.rdf.every, 1);
  }
  if (spec.msd.enabled) check_at_least("analysis.msd.every", spec.msd.every, 1);
}

// [analysis.fields] / [[analysis.fields]]: the grid, the region, the species selection, centring and fit.
void validate_fields(SimulationSpec& spec) {
  std::vector<std::string_view> names;
  for (const SpeciesSpec& sp : spec.species) names.push_back(sp.name);
  const bool many = spec.fields.size() > 1;
  for (std::size_t k = 0; k < spec.fields.size(); ++k) {
    FieldsSpec& f = spec.fields[k];
    const std::string key = many ? fmt::format("analysis.fields[{}]", k) : std::string("analysis.fields");
    const bool name_ok = !f.name.empty() && std::all_of(f.name.begin(), f.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
    });
    if (!name_ok) fail(key + ".name", show(f.name), "must be non-empty and use only letters, digits, '_' and '-' (it names the output files)");
    for (std::size_t prev = 0; prev < k; ++prev)
      if (spec.fields[prev].name == f.name)
        fail(key + ".name", show(f.name),
             fmt::format("also the name of analysis.fields[{}]; each grid needs its own name (its output files)", prev));
    double total = 1;
    for (std::size_t d = 0; d < 3; ++d) {
      check_at_least(fmt::format("{}.bins[{}]", key, d), f.bins[d], 1);
      total *= f.bins[d];
    }
    constexpr double kMaxBins = 4.0e6;  // running sums are (species + 6) 16-byte integers per bin
    if (total > kMaxBins)
      fail(key + ".bins", fmt::format("[{}, {}, {}]", f.bins[0], f.bins[1], f.bins[2]),
           fmt::format("{:.0f} bins in all, more than the {:.0f} allowed", total, kMaxBins));
    if (f.lo) check(key + ".lo", *f.lo, kFinite);
    if (f.hi) check(key + ".hi", *f.hi, kFinite);
    for (std::size_t d = 0; d < 3; ++d) {
      f.region_lo[d] = f.lo ? (*f.lo)[d] : 0.0;
      f.region_hi[d] = f.hi ? (*f.hi)[d] : spec.box[d];
      if (f.region_lo[d] < 0.0 || f.region_lo[d] >= spec.box[d])
        fail(fmt::format("{}.lo[{}]", key, d), show(f.region_lo[d]), fmt::format("must be in [0, {}) (system.box[{}])", spec.box[d], d));
      if (!(f.region_hi[d] > f.region_lo[d]) || f.region_hi[d] > spec.box[d])
        fail(fmt::format("{}.hi[{}]", key, d), show(f.region_hi[d]),
             fmt::format("must be > lo[{}] = {} and <= system.box[{}] = {}", d, f.region_lo[d], d, spec.box[d]));
    }
    check_at_least(key + ".every", f.every, 1);
    check_at_least(key + ".blocks", f.blocks, 2);
    if (!f.species.empty() && !f.exclude.empty())
      fail(key + ".exclude", show(f.exclude), fmt::format("not allowed together with {}.species (name the species binned, or those left out)", key));
    const bool by_name = !f.species.empty();
    const std::vector<std::string>& listed = by_name ? f.species : f.exclude;
    const std::string list_key = key + (by_name ? ".species" : ".exclude");
    std::vector<bool> listed_flag(names.size(), false);
    for (const std::string& n : listed) {
      const auto it = std::find(names.begin(), names.end(), n);
      if (it == names.end())
        fail(list_key, show(listed), fmt::format("unknown species \"{}\" (defined: {})", n, quoted_list(names)));
      const auto idx = static_cast<std::size_t>(it - names.begin());
      if (listed_flag[idx]) fail(list_key, show(listed), fmt::format("species \"{}\" is listed twice", n));
      listed_flag[idx] = true;
    }
    f.selected.clear();
    for (std::size_t s = 0; s < names.size(); ++s)
      if (by_name ? listed_flag[s] : !listed_flag[s]) f.selected.push_back(static_cast<int>(s));
    if (f.selected.empty()) fail(list_key, show(listed), "leaves no species to bin");
    if (f.centre_axis >= 0 && !spec.periodic[static_cast<std::size_t>(f.centre_axis)])
      fail(key + ".centre", show_axis(f.centre_axis), "centring needs a periodic axis (system.periodic)");
    if (f.fit == FieldsFit::Slab) {
      int profile_axes = 0, axis = -1;
      for (int d = 0; d < 3; ++d)
        if (f.bins[static_cast<std::size_t>(d)] > 1) ++profile_axes, axis = d;
      if (profile_axes != 1)
        fail(key + ".fit", "\"slab\"",
             fmt::format("fits a 1-D density profile: {}.bins must be > 1 along exactly one axis, e.g. [1, 1, 100]", key));
      if (f.bins[static_cast<std::size_t>(axis)] < 8)
        fail(fmt::format("{}.bins[{}]", key, axis), fmt::format("{}", f.bins[static_cast<std::size_t>(axis)]),
             "must be >= 8 for fit = \"slab\" (the tanh profile has five parameters)");
    }
  }
}

// What the engine refuses at construction on any number of ranks, checked here so that a spec that
// validates also starts (mesodpd check then refuses what mesodpd run would).
// Parses a molecule sequence in the notation of seed 002 ("Amphiphilic Systems"): "A10", "H2T6",
// "H3(T4)2" (a parenthesised group repeated n times, every copy bonded to the bead before the group).
// Fills beads (species), bonds and, with angles, every pair of bonds that share a bead.
void build_molecule(const SimulationSpec& spec, std::size_t k, MoleculeSpec& m) {
  const std::string key = fmt::format("molecule[{}].sequence", k);
  const std::string& s = m.sequence;
  m.beads.clear();
  m.bonds.clear();
  m.angles.clear();
  std::size_t pos = 0;
  auto species_of = [&](const std::string& name) {
    for (std::size_t t = 0; t < spec.species.size(); ++t)
      if (spec.species[t].name == name) return static_cast<int>(t);
    fail(key, show(s), fmt::format("names species '{}', which no [[species]] block defines", name));
  };
  auto number = [&]() {
    const std::size_t start = pos;
    while (pos < s.size() && std::isdigit(static_cast<unsigned char>(s[pos]))) ++pos;
    if (pos == start || pos - start > 6)
      fail(key, show(s), fmt::format("expected a count (1 to 999999) at position {}", start + 1));
    const int v = std::stoi(s.substr(start, pos - start));
    if (v < 1) fail(key, show(s), fmt::format("a count must be at least 1 (position {})", start + 1));
    return v;
  };
  auto name = [&]() {
    const std::size_t start = pos;
    while (pos < s.size() && (std::isalpha(static_cast<unsigned char>(s[pos])) || s[pos] == '_')) ++pos;
    if (pos == start) fail(key, show(s), fmt::format("expected a species name at position {}", start + 1));
    return s.substr(start, pos - start);
  };
  // Appends `count` beads of `sp` as a linear run bonded to `parent` (-1: none).
  auto run = [&](int sp, int count, int parent) {
    for (int c = 0; c < count; ++c) {
      const int b = static_cast<int>(m.beads.size());
      m.beads.push_back(sp);
      if (parent >= 0) m.bonds.push_back({parent, b});
      parent = b;
    }
  };
  bool branched = false;
  while (pos < s.size()) {
    if (branched) fail(key, show(s), "nothing may follow a repeated (parenthesised) group");
    const int last = static_cast<int>(m.beads.size()) - 1;
    if (s[pos] == '(') {
      if (last < 0) fail(key, show(s), "a repeated group needs beads before it to attach to");
      ++pos;
      const int sp = species_of(name());
      const int count = number();
      if (pos >= s.size() || s[pos] != ')') fail(key, show(s), fmt::format("expected ')' at position {}", pos + 1));
      ++pos;
      const int copies = number();
      for (int c = 0; c < copies; ++c) run(sp, count, last);
      branched = true;
    } else {
      const int sp = species_of(name());
      run(sp, number(), last);
    }
  }
  if (m.beads.empty()) fail(key, show(s), "is empty");
  if (m.beads.size() > 1000000) fail(key, show(s), "more than 1,000,000 beads in one molecule");
  if (m.angle_type_index >= 0) {
    std::vector<std::vector<int>> nb(m.beads.size());
    for (const auto& b : m.bonds) {
      nb[static_cast<std::size_t>(b[0])].push_back(b[1]);
      nb[static_cast<std::size_t>(b[1])].push_back(b[0]);
    }
    for (std::size_t c = 0; c < nb.size(); ++c)
      for (std::size_t x = 0; x < nb[c].size(); ++x)
        for (std::size_t y = x + 1; y < nb[c].size(); ++y) m.angles.push_back({nb[c][x], static_cast<int>(c), nb[c][y]});
  }
}

void validate_topology(SimulationSpec& spec) {
  check("bonds.reach", spec.bond_reach_set, kCutoff);
  if (spec.bond_reach_set && *spec.bond_reach_set < largest_cutoff(spec))
    fail("bonds.reach", show(*spec.bond_reach_set),
         fmt::format("must be at least the largest pair cutoff {}", largest_cutoff(spec)));
  spec.bond_reach = spec.bond_reach_set.value_or(largest_cutoff(spec));
  const double reach = spec.bond_reach;
  for (std::size_t k = 0; k < spec.bond_types.size(); ++k) {
    BondTypeSpec& b = spec.bond_types[k];
    const std::string key = fmt::format("bond_type[{}]", k);
    if (!valid_species_name(b.name)) fail(key + ".name", show(b.name), "must be non-empty and use only letters, digits and '_'");
    for (std::size_t prev = 0; prev < k; ++prev)
      if (spec.bond_types[prev].name == b.name)
        fail(key + ".name", show(b.name), fmt::format("duplicate bond type name (also bond_type[{}].name)", prev));
    if (b.style != BondStyleSpec::Wlc) check(key + ".k", b.k, kNonNegative);
    if (b.style == BondStyleSpec::Harmonic) {
      check(key + ".r0", b.r0, kNonNegative);
      if (b.r0 >= reach)
        fail(key + ".r0", show(b.r0), fmt::format("must be shorter than bonds.reach = {} (the reach of the ghost "
                                                  "layer that holds bonded partners)", reach));
    } else {
      check(key + ".rmax", b.rmax, kPositive);
    }
    if (b.style == BondStyleSpec::Wlc) check(key + ".persistence", b.persistence, kPositive);
  }
  for (std::size_t k = 0; k < spec.angle_types.size(); ++k) {
    AngleTypeSpec& a = spec.angle_types[k];
    const std::string key = fmt::format("angle_type[{}]", k);
    if (!valid_species_name(a.name)) fail(key + ".name", show(a.name), "must be non-empty and use only letters, digits and '_'");
    for (std::size_t prev = 0; prev < k; ++prev)
      if (spec.angle_types[prev].name == a.name)
        fail(key + ".name", show(a.name), fmt::format("duplicate angle type name (also angle_type[{}].name)", prev));
    check(key + ".k", a.k, kNonNegative);
    check(key + ".theta0", a.theta0_deg, Range{0.0, 180.0, true, true});
  }
  const double volume = spec.box[0] * spec.box[1] * spec.box[2];
  for (std::size_t k = 0; k < spec.molecules.size(); ++k) {
    MoleculeSpec& m = spec.molecules[k];
    const std::string key = fmt::format("molecule[{}]", k);
    if (!valid_species_name(m.name)) fail(key + ".name", show(m.name), "must be non-empty and use only letters, digits and '_'");
    m.bond_type_index = -1;
    for (std::size_t t = 0; t < spec.bond_types.size(); ++t)
      if (spec.bond_types[t].name == m.bond_type) m.bond_type_index = static_cast<int>(t);
    if (m.bond_type_index < 0)
      fail(key + ".bond_type", show(m.bond_type), "names no [[bond_type]] (a bond type without parameters)");
    m.angle_type_index = -1;
    if (!m.angle_type.empty()) {
      for (std::size_t t = 0; t < spec.angle_types.size(); ++t)
        if (spec.angle_types[t].name == m.angle_type) m.angle_type_index = static_cast<int>(t);
      if (m.angle_type_index < 0)
        fail(key + ".angle_type", show(m.angle_type), "names no [[angle_type]] (an angle type without parameters)");
    }
    build_molecule(spec, k, m);
    const BondTypeSpec& bt = spec.bond_types[static_cast<std::size_t>(m.bond_type_index)];
    const double limit = bt.style == BondStyleSpec::Harmonic ? reach : std::min(reach, bt.rmax);
    check(key + ".bond_length", m.bond_length, kPositive);
    if (m.bond_length >= limit)
      fail(key + ".bond_length", show(m.bond_length),
           fmt::format("must be shorter than {} (bonds.reach{})", limit,
                       bt.style == BondStyleSpec::Harmonic ? "" : " and the bond type's rmax"));
    check(key + ".density", m.density, kPositive);
    if (m.density) {
      const double n = std::round(*m.density * volume / static_cast<double>(m.beads.size()));
      if (n > 1.0e9) fail(key + ".density", show(*m.density), "gives more than 1e9 molecules");
      m.count = static_cast<std::uint64_t>(n);
    }
  }
}

void validate_engine_limits(SimulationSpec& spec) {
  // Particle ids are 32-bit (1..N, LAMMPS style).
  if (spec.data_file.empty()) {
    std::uint64_t total = 0;
    for (const MoleculeSpec& m : spec.molecules) total += m.count * m.beads.size();
    if (total > std::numeric_limits<std::uint32_t>::max())
      fail("molecule", "", fmt::format("{} molecule beads exceed the 32-bit id range", total));
    for (std::size_t k = 0; k < spec.species.size(); ++k) {
      const SpeciesSpec& sp = spec.species[k];
      total += sp.count;
      if (total > std::numeric_limits<std::uint32_t>::max()) {
        const bool by_density = sp.density.has_value();
        fail(species_key(k, by_density ? "density" : "count"), by_density ? show(*sp.density) : fmt::format("{}", sp.count),
             fmt::format("brings the system to {} particles, more than the {} that 32-bit particle ids allow", total,
                         std::numeric_limits<std::uint32_t>::max()));
      }
    }
  }
  // Minimum image needs every box length to be at least twice the longest interaction range (pair
  // cutoff, or the reach of bonds).
  const double cutoff = std::max(largest_cutoff(spec), spec.bond_reach);
  for (std::size_t d = 0; d < 3; ++d)
    if (spec.box[d] < 2.0 * cutoff)
      fail("system.box", fmt::format("[{}, {}, {}]", spec.box[0], spec.box[1], spec.box[2]),
           fmt::format("every length must be >= 2 x the largest cutoff (max rc, rd = {}), i.e. >= {}", cutoff, 2.0 * cutoff));

  // The domain decomposition's limits that a parallel.grid implies whatever the rank count: an axis
  // split over p > 1 ranks needs p cells and, if periodic, at least 3, and any split (more than one
  // rank) needs at most 32,000 cells along every axis (ghost records carry 16-bit cell coordinates) and
  // at least 3 along every periodic one (a bounded axis does not wrap, so fewer do not alias).
  const std::array<int, 3>& grid = spec.parallel_grid;
  const double range = cutoff + (spec.neighbor == NeighborMethod::Verlet ? spec.skin : 0.0);
  std::array<double, 3> cells{};
  for (std::size_t d = 0; d < 3; ++d) cells[d] = std::max(1.0, std::floor(spec.box[d] / range));
  const char* axes = "xyz";
  // Cells are indexed with int on each rank. Past 2^31 - 1 cells in all, only a decomposed run can
  // start, and only if no axis holds more than 32,000 cells.
  const double total_cells = cells[0] * cells[1] * cells[2];
#ifdef MESODPD_HAVE_MPI
  const bool can_split = std::max({cells[0], cells[1], cells[2]}) <= 32000;
#else
  const bool can_split = false;  // a build without MPI always runs on one rank
#endif
  if (total_cells > INT_MAX && !can_split)
    fail("system.box", fmt::format("[{}, {}, {}]", spec.box[0], spec.box[1], spec.box[2]),
         fmt::format("makes {:.3g} neighbour cells of width {:.4g} (largest cutoff + skin), more than the {} one rank can "
                     "index{}", total_cells, range, INT_MAX,
                     can_split ? "" : " (and a build with MPI splits only up to 32,000 cells along each axis)"));
  double fixed = 1;
  for (std::size_t d = 0; d < 3; ++d) fixed *= std::max(1, grid[d]);
  if (fixed > INT_MAX)
    fail("parallel.grid", fmt::format("[{}, {}, {}]", grid[0], grid[1], grid[2]),
         fmt::format("needs at least {} ranks, more than MPI can start", fixed));
  for (std::size_t d = 0; d < 3; ++d)
    if (grid[d] > 1 && (grid[d] > cells[d] || (spec.periodic[d] && cells[d] < 3)))
      fail(fmt::format("parallel.grid[{}]", d), fmt::format("{}", grid[d]),
           fmt::format("{} ranks along {} would make domains {:.4g} wide, thinner than the ghost width {:.4g} "
                       "(largest cutoff + skin) or fewer than 3 cells ({} along {}); use fewer ranks along {} or a larger box",
                       grid[d], axes[d], spec.box[d] / grid[d], range, cells[d], axes[d], axes[d]));
  if (fixed > 1)
    for (std::size_t d = 0; d < 3; ++d) {
      const std::string key = fmt::format("system.box[{}]", d);
      if (spec.periodic[d] && cells[d] < 3)
        fail(key, show(spec.box[d]),
             fmt::format("parallel.grid asks for {} ranks or more, and under MPI every box length must hold at least 3 "
                         "cells of width {:.4g} (largest cutoff + skin)", fixed, range));
      if (cells[d] > 32000)
        fail(key, show(spec.box[d]),
             fmt::format("{} cells along {} exceed the 32,000 a decomposed run supports (parallel.grid asks for {} "
                         "ranks or more)", cells[d], axes[d], fixed));
    }
}

// The sections in the order they run: a section may use what an earlier one resolved (species counts
// need the box; pairs need the species; the engine limits need the pairs). A new part of the schema
// adds its function here.
using Section = void (*)(SimulationSpec&);
constexpr Section kSections[] = {
    validate_system, validate_init,   validate_species,    validate_pairs,    validate_integrator,
    validate_run,    validate_neighbor, validate_parallel, validate_output,   validate_poiseuille,
    validate_analysis, validate_fields, validate_topology, validate_engine_limits,
};

}  // namespace

void validate(SimulationSpec& spec) {
  for (const Section section : kSections) section(spec);
}

}  // namespace mesodpd
