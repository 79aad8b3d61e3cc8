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

#include "analysis/analysis_keys.hpp"
#include "boundary/boundary_keys.hpp"
#include "boundary/geometry.hpp"
#include "engine/bonded_keys.hpp"
#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/run_keys.hpp"
#include "integrate/integrator_keys.hpp"
#include "core/particle_data.hpp"
#include "io/frame.hpp"
#include "schema/species_keys.hpp"

namespace mesodpd {

namespace {

// ---------------------------------------------------------------------------------------------
// Values as text, and the checks every section uses

using keys::show;
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

using keys::check;
using keys::fail;
using keys::kCutoff;
using keys::kFinite;
using keys::kInf;
using keys::kNonNegative;
using keys::kPositive;
using keys::Range;

void check(const std::string& key, const std::optional<double>& v, Range r) {
  if (v) check(key, *v, r);
}

std::string species_key(std::size_t k, std::string_view field) { return fmt::format("species[{}].{}", k, field); }

// The largest interaction range of any pair (the pairs are resolved by then).
double largest_cutoff(const SimulationSpec& spec) {
  double cutoff = 0.0;
  for (const PairSpec& p : spec.pairs) cutoff = std::max(cutoff, pair_range(p, spec.pair_style));
  return cutoff;
}

// ---------------------------------------------------------------------------------------------
// Sections

void validate_system(SimulationSpec& spec) {
  system_keys().check("system", spec);
  const auto& per = spec.periodic;
  // A bounded axis needs solids ([[solid]]) closing both of its faces; validate_walls checks that they
  // do. Without any solid nothing would keep the particles in.
  if (!(per[0] && per[1] && per[2]) && spec.solids.empty()) {
    for (std::size_t k = 0; k < spec.species.size(); ++k)
      for (std::size_t d = 0; d < 3; ++d)
        if (!per[d] && spec.species[k].body_force[d] != 0)
          fail(species_key(k, "body_force"), fmt::format("[{}, {}, {}]", spec.species[k].body_force[0],
                                                          spec.species[k].body_force[1], spec.species[k].body_force[2]),
               fmt::format("pushes along {}, which is bounded (system.periodic) with no [[solid]] walls to hold the "
                           "fluid; add walls or make the axis periodic", "xyz"[d]));
    fail("system.periodic", fmt::format("[{}, {}, {}]", per[0], per[1], per[2]),
         "a bounded axis (false) needs [[solid]] walls to close it; add walls or use [true, true, true]");
  }
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

// The pair laws' [[species]] keys (kSpeciesOwn) of species k: ranges, refused where the style's law does
// not read them, required ones present; then the law's defaults fill the rest.
void validate_species_law_keys(std::size_t k, SpeciesSpec& sp, PairStyle style) {
  const PairLawInfo& law = pair_law(style);
  for (const auto& [name, value] : sp.own) {
    const auto in = [&](const PairLawInfo& l) {
      return std::any_of(l.species_own.begin(), l.species_own.end(), [&](const LawKey& key) { return key.name == name; });
    };
    if (!in(law)) {
      std::string users;
      for (const PairLawInfo& other : pair_law_infos())
        if (in(other)) users += fmt::format("{}\"{}\"", users.empty() ? "" : ", ", other.style);
      fail(species_key(k, name), show(value),
           fmt::format("not used with pair.style = \"{}\" (only with pair.style = {})", law.style, users));
    }
    const LawKey& key = *std::find_if(law.species_own.begin(), law.species_own.end(),
                                      [&](const LawKey& key) { return key.name == name; });
    check(species_key(k, name), value, Range{key.lo, key.hi, key.lo_closed, key.hi_closed});
  }
  for (const LawKey& key : law.species_own) {
    if (sp.own.count(key.name) > 0) continue;
    if (key.required)
      fail(species_key(k, key.name), "",
           fmt::format("missing: pair.style = \"{}\" needs {} for every species (no default)", law.style, key.hint));
    sp.own[std::string(key.name)] = key.fallback;
  }
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
    species_keys().check(fmt::format("species[{}]", k), sp);
    validate_species_law_keys(k, sp, spec.pair_style);
    if (mixing == Mixing::Geometric && !sp.a)
      fail(species_key(k, "a"), "", "missing: pair.mixing = \"geometric\" needs a for every species");
    if (mixing == Mixing::Explicit && sp.a)
      fail(species_key(k, "a"), show(*sp.a),
           "only used with pair.mixing = \"geometric\"; use pair.a or [[pair.override]] instead");
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

// The shared key `name` of a PairParams.
std::optional<double> PairParams::*shared_member(std::string_view name) {
  if (name == "a") return &PairParams::a;
  if (name == "gamma") return &PairParams::gamma;
  if (name == "sigma") return &PairParams::sigma;
  if (name == "rc") return &PairParams::rc;
  if (name == "rd") return &PairParams::rd;
  return &PairParams::s;
}

// The own key `name` as the first law that declares it declares it.
const LawKey* own_key(std::string_view name) {
  for (const PairLawInfo& law : pair_law_infos())
    for (const LawKey& k : law.own)
      if (k.name == name) return &k;
  return nullptr;
}


void validate_pair_params(const std::string& prefix, const PairParams& p, PairStyle style) {
  const PairLawInfo& law = pair_law(style);
  // Many-body DPD's A_ij is attractive (negative) in Warren's liquid; the other laws repel with a >= 0.
  check(prefix + ".a", p.a, Range{law.min_a, kInf, true, true});
  check(prefix + ".gamma", p.gamma, kNonNegative);
  check(prefix + ".sigma", p.sigma, kNonNegative);
  check(prefix + ".rc", p.rc, kCutoff);
  check(prefix + ".rd", p.rd, kCutoff);
  check(prefix + ".s", p.s, kCutoff);
  for (const auto& [name, value] : p.own) {
    const LawKey* k = own_key(name);
    if (!k) fail(prefix + "." + name, show(value), "is not a key of any pair law");
    check(prefix + "." + name, value, Range{k->lo, k->hi, k->lo_closed, k->hi_closed});
  }
  // Keys the style does not read would be silently ignored: refuse them.
  const auto users = [](std::string_view name) {
    std::string out;
    for (const PairLawInfo& other : pair_law_infos()) {
      const bool uses = std::find(other.shared.begin(), other.shared.end(), name) != other.shared.end() ||
                        std::any_of(other.own.begin(), other.own.end(), [&](const LawKey& k) { return k.name == name; });
      if (uses) out += fmt::format("{}\"{}\"", out.empty() ? "" : ", ", other.style);
    }
    return out;
  };
  for (const std::string_view name : kSharedPairKeys) {
    const std::optional<double>& v = p.*shared_member(name);
    if (!v || std::find(law.shared.begin(), law.shared.end(), name) != law.shared.end()) continue;
    if (!law.noise && name != "a" && name != "rc")
      fail(prefix + "." + std::string(name), show(*v),
           fmt::format("not used with pair.style = \"{}\" (a conservative law without dissipative or random force)",
                       law.style));
    fail(prefix + "." + std::string(name), show(*v),
         fmt::format("not used with pair.style = \"{}\" (only with pair.style = {})", law.style, users(name)));
  }
  for (const auto& [name, value] : p.own)
    if (std::none_of(law.own.begin(), law.own.end(), [&](const LawKey& k) { return k.name == name; }))
      fail(prefix + "." + name, show(value),
           fmt::format("not used with pair.style = \"{}\" (only with pair.style = {})", law.style, users(name)));
}

// A law's message (LawProblem::why) with its {value} and {pair} filled in.
std::string law_message(const LawProblem& problem, const std::string& pair_names) {
  std::string why = problem.why;
  const auto put = [&](std::string_view token, const std::string& text) {
    if (const auto at = why.find(token); at != std::string::npos) why.replace(at, token.size(), text);
  };
  put("{value}", show(problem.other));
  put("{pair}", pair_names);
  return why;
}

// Resolves every unordered species pair: override > (geometric mixing for a | [pair]) > default.
void validate_pairs(SimulationSpec& spec) {
  const PairSection& sec = spec.pair_section;
  validate_pair_params("pair", sec.params, spec.pair_style);
  if (sec.kernel && !pair_law(spec.pair_style).density) {
    std::string with;
    for (const PairLawInfo& law : pair_law_infos())
      if (law.density) with += fmt::format("{}pair.style = \"{}\"", with.empty() ? "" : " or ", law.style);
    fail("pair.kernel", show(std::string(density_kernel_name(density_kernel_of(spec)))),
         fmt::format("only used with {} (the laws with a local-density pass)", with));
  }
  if (const PairLawInfo& law = pair_law(spec.pair_style); sec.kernel && law.density) {
    const DensityKernelKind kind = density_kernel_of(spec);
    if (std::find(law.kernels.begin(), law.kernels.end(), kind) == law.kernels.end())
      fail("pair.kernel", show(std::string(density_kernel_name(kind))),
           fmt::format("not for pair.style = \"{}\"{}", law.style,
                       kind == DensityKernelKind::Warren
                           ? ": the gradient of Warren's kernel does not vanish at r = 0, so the pair force "
                             "F(r) = -W'(r)/r diverges; use \"lucy\" or \"wendland\""
                           : ""));
  }
  if (spec.pair_style == PairStyle::Mdpd && sec.mixing == Mixing::Geometric)
    fail("pair.mixing", "\"geometric\"",
         "not available with pair.style = \"mdpd\" (A_ij is usually negative); set pair.a and [[pair.override]]");
  if (const PairLawInfo& law = pair_law(spec.pair_style);
      sec.mixing == Mixing::Geometric && std::find(law.shared.begin(), law.shared.end(), "a") == law.shared.end())
    fail("pair.mixing", "\"geometric\"",
         fmt::format("not used with pair.style = \"{}\" (the law has no a_ij to mix)", law.style));
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
    validate_pair_params(key, o.params, spec.pair_style);
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
      const std::string pair_names = fmt::format("species pair ({}, {})", names[i], names[j]);
      // A value the style needs that neither the override nor [pair] gives.
      const PairLawInfo& law = pair_law(spec.pair_style);
      const auto missing = [&](std::string_view name, std::string_view what) {
        fail(fmt::format("{}.{}", k != kNone ? ov_key : std::string("pair"), name), "",
             fmt::format("missing for {}: pair.style = \"{}\" needs {} (no default)", pair_names, law.style, what));
      };
      for (const auto& [name, hint] : law.required) {
        const auto v = pick(shared_member(name));
        if (!v) missing(name, hint);
        (name == "a" ? p.a : name == "rd" ? p.rd : name == "rc" ? p.rc : name == "gamma" ? p.gamma : p.s) = *v;
      }
      for (const LawKey& key : law.own) {
        const auto from = [&](const PairParams* params) -> const double* {
          if (!params) return nullptr;
          const auto it = params->own.find(key.name);
          return it == params->own.end() ? nullptr : &it->second;
        };
        const double* v = from(ov) ? from(ov) : from(&sec.params);
        if (!v && key.required) missing(key.name, key.hint);
        p.own[std::string(key.name)] = v ? *v : key.fallback;
      }
      // The law's own checks on the resolved pair.
      const LawProblem problem = law.problem(pair_values(p, spec));
      if (problem.why) {
        const bool shared =
            std::find(kSharedPairKeys.begin(), kSharedPairKeys.end(), problem.key) != kSharedPairKeys.end();
        const bool in_override = ov && (shared ? (ov->*shared_member(problem.key)).has_value()
                                               : ov->own.count(problem.key) > 0);
        const double value = !shared ? p.value(problem.key)
                             : problem.key == "a" ? p.a : problem.key == "rd" ? p.rd : problem.key == "rc" ? p.rc
                             : problem.key == "gamma" ? p.gamma : p.s;
        fail(fmt::format("{}.{}", in_override ? ov_key : std::string("pair"), problem.key), show(value),
             law_message(problem, pair_names));
      }

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

void validate_integrator(SimulationSpec& spec) { integrator_keys().check("integrator", spec); }

void validate_run(SimulationSpec& spec) { run_keys().check("run", spec); }

void validate_neighbor(SimulationSpec& spec) { neighbor_keys().check("neighbor", spec); }

void validate_parallel(SimulationSpec& spec) { parallel_keys().check("parallel", spec); }

void validate_output(SimulationSpec& spec) {
  output_keys().check("output", spec);
  DumpSpec& d = spec.dump;
  if (!d.enabled) return;
  dump_keys().check("output.dump", d);
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
  poiseuille_keys().check("poiseuille", p);
  if (p.force == 0.0) fail("poiseuille.force", show(p.force), "must be non-zero");
  if (p.flow_axis == p.gradient_axis)
    fail("poiseuille.gradient_axis", show_axis(p.gradient_axis),
         fmt::format("must differ from poiseuille.flow_axis ({})", show_axis(p.flow_axis)));
  if (p.bins % 2 != 0) fail("poiseuille.bins", fmt::format("{}", p.bins), "must be even (the two flow halves get equal bins)");
}

void validate_analysis(SimulationSpec& spec) {
  if (spec.rdf.enabled) {
    rdf_keys().check("analysis.rdf", spec.rdf);
    const double half_box = 0.5 * std::min({spec.box[0], spec.box[1], spec.box[2]});
    if (!(spec.rdf.rmax < half_box))
      fail("analysis.rdf.rmax", show(spec.rdf.rmax), fmt::format("must be < half the smallest box length ({})", half_box));
  }
  if (spec.msd.enabled) msd_keys().check("analysis.msd", spec.msd);
  if (spec.surface_tension.enabled) surface_tension_keys().check("analysis.surface_tension", spec.surface_tension);
  if (spec.droplet.enabled) {
    const DropletSpec& d = spec.droplet;
    const auto& per = spec.periodic;
    // The drop's centre is a periodic mean and the vapour region wraps round the box.
    if (!(per[0] && per[1] && per[2]))
      fail("analysis.droplet", fmt::format("system.periodic = [{}, {}, {}]", per[0], per[1], per[2]),
           "a droplet in its vapour needs a box periodic along every axis");
    if (d.inner_radius == 0) fail("analysis.droplet.inner_radius", "missing", "is required: the radius of the liquid core where the inside pressure is measured");
    if (d.outer_radius == 0) fail("analysis.droplet.outer_radius", "missing", "is required: the radius beyond which the vapour pressure is measured");
    droplet_keys().check("analysis.droplet", d);
    const double half_box = 0.5 * std::min({spec.box[0], spec.box[1], spec.box[2]});
    if (!(d.outer_radius > d.inner_radius))
      fail("analysis.droplet.outer_radius", show(d.outer_radius),
           fmt::format("must be > analysis.droplet.inner_radius ({})", d.inner_radius));
    if (!(d.outer_radius < half_box))
      fail("analysis.droplet.outer_radius", show(d.outer_radius),
           fmt::format("must be < half the smallest box length ({}): the vapour region is the box outside that sphere", half_box));
    if (!(d.bin_width < half_box))
      fail("analysis.droplet.bin_width", show(d.bin_width), fmt::format("must be < half the smallest box length ({})", half_box));
  }
  if (spec.stress_profile.enabled) {
    const StressProfileSpec& t = spec.stress_profile;
    stress_profile_keys().check("analysis.stress_profile", t);
    // The profile's bins and the contour assignment wrap round the box along the axis.
    if (!spec.periodic[static_cast<std::size_t>(t.axis)])
      fail("analysis.stress_profile.axis", std::string(1, "xyz"[t.axis]),
           "the stress profile needs a periodic axis (the box is bounded along it)");
    if (pair_law(spec.pair_style).density && spec.bond_exclusion != BondExclusion::None)
      fail("analysis.stress_profile", fmt::format("bonds.exclude with pair.style = \"{}\"", pair_law(spec.pair_style).style),
           "the virial of excluded pairs is not removed for density-dependent forces yet");
  }
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
    fields_keys().check(key, f);
    for (const std::string& m : f.means) {
      const std::size_t index = ParticleData::field_index(m);
      const bool real = index < ParticleData::kFieldCount && ParticleData::fields()[index].kind == 'f' &&
                        ParticleData::fields()[index].elem_bytes == sizeof(double);
      if (!real) {
        std::vector<std::string_view> doubles;
        for (const FieldInfo& info : ParticleData::fields())
          if (info.kind == 'f' && info.elem_bytes == sizeof(double)) doubles.push_back(info.name);
        fail(key + ".means", show(f.means),
             fmt::format("\"{}\" is not a floating-point particle field (one of {})", m, quoted_list(doubles)));
      }
      if (std::count(f.means.begin(), f.means.end(), m) > 1)
        fail(key + ".means", show(f.means), fmt::format("\"{}\" is listed twice", m));
    }
    double total = 1;
    for (std::size_t d = 0; d < 3; ++d) total *= f.bins[d];
    constexpr double kMaxBins = 4.0e6;  // running sums are (species + 6) 16-byte integers per bin
    if (total > kMaxBins)
      fail(key + ".bins", fmt::format("[{}, {}, {}]", f.bins[0], f.bins[1], f.bins[2]),
           fmt::format("{:.0f} bins in all, more than the {:.0f} allowed", total, kMaxBins));
    for (std::size_t d = 0; d < 3; ++d) {
      f.region_lo[d] = f.lo ? (*f.lo)[d] : 0.0;
      f.region_hi[d] = f.hi ? (*f.hi)[d] : spec.box[d];
      if (f.region_lo[d] < 0.0 || f.region_lo[d] >= spec.box[d])
        fail(fmt::format("{}.lo[{}]", key, d), show(f.region_lo[d]), fmt::format("must be in [0, {}) (system.box[{}])", spec.box[d], d));
      if (!(f.region_hi[d] > f.region_lo[d]) || f.region_hi[d] > spec.box[d])
        fail(fmt::format("{}.hi[{}]", key, d), show(f.region_hi[d]),
             fmt::format("must be > lo[{}] = {} and <= system.box[{}] = {}", d, f.region_lo[d], d, spec.box[d]));
    }
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
      if (spec.species[t].name == name) {
        if (spec.species[t].frozen)
          fail(key, show(s), fmt::format("species '{}' is frozen (a wall species); molecule beads must move", name));
        return static_cast<int>(t);
      }
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
  bonds_keys().check("bonds", spec);
  if (spec.bond_reach_set && *spec.bond_reach_set < largest_cutoff(spec))
    fail("bonds.reach", show(*spec.bond_reach_set),
         fmt::format("must be at least the largest pair cutoff {}", largest_cutoff(spec)));
  spec.bond_reach = spec.bond_reach_set.value_or(largest_cutoff(spec));
  const double reach = spec.bond_reach;
  if (spec.bond_subcycles > 1) {
    if (spec.integrator != IntegratorKind::GrootWarren)
      fail("bonds.subcycles", fmt::format("{}", spec.bond_subcycles),
           "multiple time stepping splits the Groot-Warren (velocity-Verlet) step; it is not available with "
           "integrator.type = \"euler\"");
    if (!spec.solids.empty())
      fail("bonds.subcycles", fmt::format("{}", spec.bond_subcycles),
           "not available with [[solid]] walls yet: the walls reflect a particle from its predicted move over a "
           "whole step, which the inner steps would change");
    if (spec.molecules.empty() && spec.data_file.empty())
      fail("bonds.subcycles", fmt::format("{}", spec.bond_subcycles),
           "there are no bonds to subcycle: add [[molecule]] blocks or read a data file with a Bonds section");
  }
  // Each [[bond_type]], [[angle_type]] and [[dihedral_type]]: a valid, unique name and the keys of its style.
  const auto named_types = [&](auto& types, const char* table, const char* what, const auto& keys, const auto& more) {
    for (std::size_t k = 0; k < types.size(); ++k) {
      auto& t = types[k];
      const std::string key = fmt::format("{}[{}]", table, k);
      if (!valid_species_name(t.name)) fail(key + ".name", show(t.name), "must be non-empty and use only letters, digits and '_'");
      for (std::size_t prev = 0; prev < k; ++prev)
        if (types[prev].name == t.name)
          fail(key + ".name", show(t.name), fmt::format("duplicate {} type name (also {}[{}].name)", what, table, prev));
      keys.check(key, t);  // the keys of its style
      more(key, t);
    }
  };
  named_types(spec.bond_types, "bond_type", "bond", bond_type_keys(), [&](const std::string& key, const BondTypeSpec& b) {
    if (b.style == BondStyleSpec::Harmonic && b.r0 >= reach)
      fail(key + ".r0", show(b.r0), fmt::format("must be shorter than bonds.reach = {} (the reach of the ghost "
                                                "layer that holds bonded partners)", reach));
  });
  named_types(spec.angle_types, "angle_type", "angle", angle_type_keys(), [](const std::string&, const AngleTypeSpec&) {});
  named_types(spec.dihedral_types, "dihedral_type", "dihedral", dihedral_type_keys(),
              [](const std::string&, const DihedralTypeSpec&) {});
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
    molecule_keys().check(key, m);
    if (m.bond_length >= limit)
      fail(key + ".bond_length", show(m.bond_length),
           fmt::format("must be shorter than {} (bonds.reach{})", limit,
                       bt.style == BondStyleSpec::Harmonic ? "" : " and the bond type's rmax"));
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
    // A run of nothing would end with exit 0 and a temperature of 0. Models may place particles of their
    // own (membrane vertices, engine/installer.hpp Model::place).
    if (total == 0)
      for (const Model& m : models())
        if (m.place) total += m.place(spec).size();
    if (total == 0 && !spec.species.empty()) {
      const SpeciesSpec& first = spec.species.front();
      const bool by_density = first.density.has_value();
      fail(species_key(0, by_density ? "density" : "count"), by_density ? show(*first.density) : "0",
           spec.species.size() == 1 && spec.molecules.empty()
               ? std::string("the system is empty (no particles in the box); give a count >= 1 or a density")
               : std::string("the system is empty: every species has count 0 (from its count or density) and no "
                             "[[molecule]] adds beads; give some species a count >= 1 or a density"));
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

// [[solid]] blocks and [walls]: shapes, their species, the box faces they close, and the fluid they leave.
void validate_shape(const std::string& key, const ShapeSpec& sh, const SimulationSpec& spec, double depth) {
  auto nonzero = [&](const std::string& k, const std::array<double, 3>& v) {
    if (v[0] == 0 && v[1] == 0 && v[2] == 0) fail(k, "[0, 0, 0]", "must not be the zero vector");
  };
  // A solid thinner than the interaction range lets the fluid on either side interact through it.
  auto thick_enough = [&](const std::string& k, double thickness) {
    if (thickness < depth)
      fail(k, show(thickness), fmt::format("gives a solid {} thick, thinner than walls.depth = {} (the largest "
                                           "cutoff): fluid would interact through it", thickness, depth));
  };
  shape_keys().check(key, sh);  // the ranges of the keys the shape reads
  switch (sh.kind) {
    case ShapeKind::Plane:
      nonzero(key + ".normal", sh.normal);
      // A half space cannot be periodic: along a periodic axis its far side would meet the fluid.
      for (std::size_t d = 0; d < 3; ++d)
        if (sh.normal[d] != 0 && spec.periodic[d])
          fail(key + ".normal", fmt::format("[{}, {}, {}]", sh.normal[0], sh.normal[1], sh.normal[2]),
               fmt::format("has a component along {}, which is periodic; a plane's normal must lie along bounded axes "
                           "(system.periodic), or use shape = \"box\" for a slab", "xyz"[d]));
      break;
    case ShapeKind::Cylinder:
      nonzero(key + ".direction", sh.direction);
      thick_enough(key + ".radius", 2 * sh.radius);
      break;
    case ShapeKind::Sphere:
      thick_enough(key + ".radius", 2 * sh.radius);
      break;
    case ShapeKind::Box:
      for (std::size_t d = 0; d < 3; ++d) {
        if (!(sh.hi[d] > sh.lo[d]))
          fail(fmt::format("{}.hi[{}]", key, d), show(sh.hi[d]), fmt::format("must exceed {}.lo[{}] = {}", key, d, sh.lo[d]));
        // Only where the box ends inside the simulation box does the fluid meet both of its sides.
        if (sh.lo[d] > 0 || sh.hi[d] < spec.box[d]) thick_enough(fmt::format("{}.hi[{}]", key, d), sh.hi[d] - sh.lo[d]);
      }
      break;
    case ShapeKind::Pillars: {
      thick_enough(key + ".radius", 2 * sh.radius);
      if (sh.spacing <= 2 * sh.radius)
        fail(key + ".spacing", show(sh.spacing), fmt::format("must exceed the pillar diameter 2 x {}.radius = {}", key, 2 * sh.radius));
      // The lattice must repeat with the box along the periodic in-plane axes.
      const std::size_t a0 = sh.axis == 0 ? 1 : 0, a1 = sh.axis == 2 ? 1 : 2;
      const double period[2] = {sh.spacing, sh.lattice == Lattice::Square ? sh.spacing : sh.spacing * std::sqrt(3.0)};
      const std::size_t axes[2] = {a0, a1};
      for (int q = 0; q < 2; ++q) {
        const std::size_t d = axes[q];
        const double cells = spec.box[d] / period[q];
        if (spec.periodic[d] && std::abs(cells - std::round(cells)) > 1e-6 * cells)
          fail(fmt::format("system.box[{}]", d), show(spec.box[d]),
               fmt::format("is not a multiple of the {} lattice period {} along {} ({}.spacing = {}): the pillars "
                           "would not repeat with the periodic box", sh.lattice == Lattice::Square ? "square" : "hexagonal",
                           period[q], "xyz"[d], key, sh.spacing));
      }
      break;
    }
    case ShapeKind::Image: {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(sh.file, ec)) fail(key + ".file", show(sh.file), "no such file");
      break;
    }
    case ShapeKind::Union:
    case ShapeKind::Difference:
      if (sh.parts.empty()) fail(key + ".parts", "", "needs at least one shape");
      for (std::size_t k = 0; k < sh.parts.size(); ++k)
        validate_shape(fmt::format("{}.parts[{}]", key, k), sh.parts[k], spec,
                       sh.kind == ShapeKind::Difference && k > 0 ? 0.0 : depth);
      break;
  }
}

// [[species]] region: the shape a generated species is placed in (particles falling inside a
// [[solid]] still become its wall particles). Its shape keys are checked as a solid's, without the
// thickness rule (no fluid lies on the far side of a region).
void validate_regions(SimulationSpec& spec) {
  for (std::size_t k = 0; k < spec.species.size(); ++k) {
    const SpeciesSpec& sp = spec.species[k];
    if (!sp.region) continue;
    if (sp.frozen)
      fail(species_key(k, "region"), "", "not allowed for a frozen species (its particles are the fluid frozen inside [[solid]] blocks)");
    if (!spec.data_file.empty())
      fail(species_key(k, "region"), "", "not allowed with init.lammps_data (particles come from the data file)");
    validate_shape(species_key(k, "region"), *sp.region, spec, 0.0);
  }
}

void validate_walls(SimulationSpec& spec) {
  WallsSpec& w = spec.walls;
  walls_keys().check("walls", w);
  if (w.depth == 0) w.depth = largest_cutoff(spec);
  if (w.adaptive_range == 0) w.adaptive_range = largest_cutoff(spec);
  if (w.adaptive && w.adaptive_range <= w.layer)
    fail("walls.adaptive_range", show(w.adaptive_range),
         fmt::format("must exceed walls.layer = {} (the force acts between the reflecting layer and the range)", w.layer));
  if (w.adaptive && spec.solids.empty())
    fail("walls.adaptive", "true", "an adaptive near-wall force needs [[solid]] walls");
  if (w.equilibrate > 0 && spec.solids.empty())
    fail("walls.equilibrate", show(static_cast<double>(w.equilibrate)), "equilibration before freezing needs [[solid]] walls");
  if (w.equilibrate > 0 && !spec.molecules.empty())
    fail("walls.equilibrate", show(static_cast<double>(w.equilibrate)),
         "not supported with [[molecule]] (molecules are placed clear of the solids, not cut from a fluid); set it to 0");
  bool any_mobile = false;
  for (std::size_t k = 0; k < spec.species.size(); ++k) {
    const SpeciesSpec& sp = spec.species[k];
    any_mobile = any_mobile || !sp.frozen;
    if (sp.frozen && (sp.body_force[0] != 0 || sp.body_force[1] != 0 || sp.body_force[2] != 0))
      fail(species_key(k, "body_force"), "", "a frozen species is never moved: a body force on it has no effect");
  }
  if (!any_mobile) fail("species", "", "every species is frozen: at least one must be a mobile fluid species");
  if (spec.solids.empty()) return;
  if (spec.poiseuille.enabled)
    fail("poiseuille", "", "reverse Poiseuille flow is for periodic boxes; between [[solid]] walls drive the flow "
                           "with [[species]] body_force");
  if (!spec.data_file.empty())
    fail("init.lammps_data", show(spec.data_file),
         "[[solid]] walls are built from a generated fluid; they cannot be combined with a data file yet");
  for (std::size_t b = 0; b < spec.solids.size(); ++b) {
    SolidSpec& s = spec.solids[b];
    const std::string key = fmt::format("solid[{}]", b);
    if (!valid_species_name(s.name))
      fail(key + ".name", show(s.name), "must be non-empty and use only letters, digits and '_'");
    for (std::size_t prev = 0; prev < b; ++prev)
      if (spec.solids[prev].name == s.name)
        fail(key + ".name", show(s.name), fmt::format("duplicate solid name (also solid[{}].name)", prev));
    s.species_index = -1;
    for (std::size_t k = 0; k < spec.species.size(); ++k)
      if (spec.species[k].name == s.species) s.species_index = static_cast<int>(k);
    if (s.species_index < 0) fail(key + ".species", show(s.species), "no [[species]] has this name");
    if (!spec.species[static_cast<std::size_t>(s.species_index)].frozen)
      fail(key + ".species", show(s.species),
           fmt::format("must be a frozen species (set frozen = true in species[{}])", s.species_index));
    solid_keys().check(key, s);
    validate_shape(key, s.shape, spec, w.depth);
    // A moving wall keeps its shape only if it slides along itself: planes moving in their own plane.
    const auto& v = s.velocity;
    if (v[0] != 0 || v[1] != 0 || v[2] != 0) {
      const auto& n = s.shape.normal;
      if (s.shape.kind != ShapeKind::Plane || std::abs(v[0] * n[0] + v[1] * n[1] + v[2] * n[2]) > 1e-12)
        fail(key + ".velocity", fmt::format("[{}, {}, {}]", v[0], v[1], v[2]),
             "only a plane may move, and only along its own surface (velocity perpendicular to its normal)");
    }
  }
  // Build the geometry once (this reads image files and checks their size against the box).
  Box box;
  box.len = {spec.box[0], spec.box[1], spec.box[2]};
  box.periodic = spec.periodic;
  Geometry geo;
  try {
    geo = Geometry(spec.solids, box);
  } catch (const SpecError&) {
    throw;
  } catch (const ConfigError& e) {
    // Image errors name the key at the start of their message.
    const std::string what = e.what();
    const std::size_t colon = what.find(": ");
    fail(colon == std::string::npos ? "solid" : what.substr(0, colon), "",
         colon == std::string::npos ? what : what.substr(colon + 2));
  }
  // Some fluid must remain: sample the box on a grid of about 0.5 r_c (at most 2^21 points).
  std::array<int, 3> n{};
  double cells = 1;
  for (std::size_t d = 0; d < 3; ++d) {
    n[d] = std::max(1, static_cast<int>(std::ceil(spec.box[d] / 0.5)));
    cells *= n[d];
  }
  const double shrink = cells > 2097152.0 ? std::cbrt(cells / 2097152.0) : 1.0;
  for (std::size_t d = 0; d < 3; ++d) n[d] = std::max(1, static_cast<int>(n[d] / shrink));
  bool fluid = false;
  for (int k = 0; k < n[2] && !fluid; ++k)
    for (int j = 0; j < n[1] && !fluid; ++j)
      for (int i = 0; i < n[0] && !fluid; ++i)
        fluid = geo.sdf(Vec3{(i + 0.5) * spec.box[0] / n[0], (j + 0.5) * spec.box[1] / n[1],
                             (k + 0.5) * spec.box[2] / n[2]}) > 0;
  if (!fluid) fail("solid", "", "the solids fill the whole box: no fluid is left between them");
  // Each face of a bounded axis must be closed by at least walls.depth of solid.
  for (int d = 0; d < 3; ++d) {
    if (spec.periodic[static_cast<std::size_t>(d)]) continue;
    const int u = d == 0 ? 1 : 0, v = d == 2 ? 1 : 2;
    const int nu = std::min(400, std::max(1, static_cast<int>(std::ceil(spec.box[static_cast<std::size_t>(u)] / 0.25))));
    const int nv = std::min(400, std::max(1, static_cast<int>(std::ceil(spec.box[static_cast<std::size_t>(v)] / 0.25))));
    // First any point of a face with no solid behind it, then any where the solid is too thin.
    for (int pass = 0; pass < 2; ++pass)
      for (int side = 0; side < 2; ++side)
        for (int b = 0; b < nv; ++b)
          for (int a = 0; a < nu; ++a) {
            double q[3];
            q[u] = (a + 0.5) * spec.box[static_cast<std::size_t>(u)] / nu;
            q[v] = (b + 0.5) * spec.box[static_cast<std::size_t>(v)] / nv;
            q[d] = side == 0 ? 0.0 : spec.box[static_cast<std::size_t>(d)];
            int body = -1;
            const double sd = geo.sdf(Vec3{q[0], q[1], q[2]}, body);
            const std::string per = fmt::format("[{}, {}, {}]", spec.periodic[0], spec.periodic[1], spec.periodic[2]);
            if (pass == 0 && sd >= 0)
              fail("system.periodic", per,
                   fmt::format("axis {} is bounded, but no [[solid]] closes its face {} = {} at ({}, {}, {}): the fluid "
                               "would leave the box", "xyz"[d], "xyz"[d], q[d], q[0], q[1], q[2]));
            if (pass == 1 && sd > -w.depth + 1e-9)
              fail("system.periodic", per,
                   fmt::format("axis {} is bounded, but the wall at its face {} = {} (solid[{}]) is only {} thick at "
                               "({}, {}, {}), thinner than walls.depth = {} (the largest cutoff): walls must hold the "
                               "fluid's whole interaction range", "xyz"[d], "xyz"[d], q[d], body, -sd, q[0], q[1], q[2],
                               w.depth));
          }
  }
}

// The sections in the order they run: a section may use what an earlier one resolved (species counts
// need the box; pairs need the species; the engine limits need the pairs). A new part of the schema
// adds its function here.
using Section = void (*)(SimulationSpec&);
constexpr Section kSections[] = {
    validate_system, validate_init,   validate_species,    validate_pairs,    validate_integrator,
    validate_run,    validate_neighbor, validate_parallel, validate_output,   validate_poiseuille,
    validate_analysis, validate_fields, validate_walls, validate_regions, validate_topology, validate_engine_limits,
};

}  // namespace

void validate(SimulationSpec& spec) {
  for (const Section section : kSections) section(spec);
  // The models' own sections (engine/installer.hpp), each checked by its declaration, after the shared
  // spec so that cross-checks see its resolved values.
  for (const Model& m : models()) {
    if (!m.section) continue;
    const ModelSection section = m.section();
    if (const auto it = spec.models.find(section.path); it != spec.models.end()) section.check(it->second, spec);
  }
}

std::vector<std::string> spec_warnings(const SimulationSpec& spec) {
  std::vector<std::string> out;
  if (spec.pair_style == PairStyle::Mdpd && !spec.pairs.empty()) {
    const PairSpec& first = spec.pairs.front();
    for (const PairSpec& p : spec.pairs)
      if (p.value("b") != first.value("b") || p.rd != first.rd) {
        out.push_back(fmt::format(
            "pair.style = \"mdpd\" with B_ij or r_d that differ between species pairs (b = {} and {}, rd = {} and "
            "{}): such a many-body force derives from no potential (Warren, Phys. Rev. E 68, 066702 (2003)), so the "
            "energy in thermo.csv is not conserved and the mixture need not reach a Boltzmann equilibrium",
            first.value("b"), p.value("b"), first.rd, p.rd));
        break;
      }
  }
  if (spec.pair_style == PairStyle::Spline) {
    // W(r, r_c) is a function of r / r_c, so its integral over space scales as r_c^3 and that of
    // U = a [A W(r, r_c1) - B W(r, r_c2)] (seed 000 Eq. 19) has the sign of a (A r_c1^3 - B r_c2^3). A
    // negative integral makes the potential catastrophic (Ruelle): the energy per particle has no lower
    // bound as the density grows, so a "liquid" keeps contracting instead of coexisting with its gas
    // (docs/validation.md, Liu's droplet phases at B = 1.05 and 1.1).
    for (const PairSpec& p : spec.pairs) {
      const double repulsion = p.value("repulsion"), rc1 = p.value("rc1"), attraction = p.value("attraction"),
                   rc2 = p.value("rc2");
      const double integral = p.a * (repulsion * std::pow(rc1, 3) - attraction * std::pow(rc2, 3));
      if (integral < 0) {
        out.push_back(fmt::format(
            "pair.style = \"spline\" for species pair ({}, {}): a (A r_c1^3 - B r_c2^3) = {:.4g} < 0 (a = {}, repulsion "
            "A = {}, rc1 = {}, attraction B = {}, rc2 = {}): the potential's integral over space is negative, so it is "
            "catastrophic (no thermodynamic limit) and dense drops keep contracting; keep B below A (r_c1 / r_c2)^3 = {:.4g}",
            spec.species[static_cast<std::size_t>(p.i)].name, spec.species[static_cast<std::size_t>(p.j)].name, integral,
            p.a, repulsion, rc1, attraction, rc2, repulsion * std::pow(rc1 / rc2, 3)));
        break;
      }
    }
  }
  // The law's own warning (law_warning) for the first species pair that has one.
  const PairLawInfo& law = pair_law(spec.pair_style);
  for (const PairSpec& p : spec.pairs) {
    const LawProblem w = law.warning(pair_values(p, spec));
    if (!w.why) continue;
    const std::string pair_names = fmt::format("species pair ({}, {})", spec.species[static_cast<std::size_t>(p.i)].name,
                                               spec.species[static_cast<std::size_t>(p.j)].name);
    out.push_back(fmt::format("pair.{}: {}", w.key, law_message(w, pair_names)));
    break;
  }
  return out;
}

}  // namespace mesodpd
