// What a pair law declares about its parameters, beside its force: its style name, the keys of [pair] and
// [[pair.override]] it reads (the shared DPD keys it uses and keys of its own, with their ranges,
// defaults and one-line docs), how a resolved species pair becomes its parameter struct, and how far the
// pair reaches. The schema reads, checks, refuses and documents the keys from this (src/schema/), and
// the engine builds the parameter tables with it (engine/pair_laws.hpp): a new law is one header.
// Host-only declarations: nothing here is called from a device.
#pragma once
#include <array>
#include <cstddef>
#include <limits>
#include <string_view>

#include "physics/density_kernel.hpp"

namespace mesodpd {

// One parameter key of a law, as written in [pair] or a [[pair.override]] (or, for a species key, in a
// [[species]] block).
struct LawKey {
  std::string_view name;
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  bool lo_closed = true, hi_closed = true;  // the allowed values
  bool required = false;                    // no default: every species pair needs a value
  double fallback = 0;                      // the default where not required
  std::string_view hint;                    // for "missing": what the key is, with a usual value
  std::string_view doc;                     // one line for docs/config.md (own keys)
};

// The keys every DPD-like law shares, in the order of docs/config.md; a law says which of them it reads
// (kShared) and may require one (kRequired). Their ranges and meanings are the schema's ([pair]).
inline constexpr std::array<std::string_view, 6> kSharedPairKeys{"a", "gamma", "sigma", "rc", "rd", "s"};

// The values of one resolved species pair as a law reads them: the shared keys (sigma already follows
// from gamma and kT, seed 000 Eq. 7; rd defaults to rc) and the law's own keys in the order of its kOwn.
// Besides, the system's kT and, for the pair's two species i and j (in the order of the table entry),
// their masses, whether they are frozen and the values of the law's species keys (kSpeciesOwn, read from [[species]]).
struct PairValues {
  double a = 25, gamma = 4.5, sigma = 3, rc = 1, rd = 1, s = 2;
  static constexpr std::size_t kMaxOwn = 16;
  std::array<double, kMaxOwn> own{};
  double kT = 1;
  double mass_i = 1, mass_j = 1;
  bool frozen_i = false, frozen_j = false;  // wall particles (never integrated: infinite mass)
  static constexpr std::size_t kMaxSpeciesOwn = 8;
  std::array<double, kMaxSpeciesOwn> species_i{}, species_j{};
  // Laws with a density pass (kDensity): the run's density kernel (pair.kernel, or the law's default).
  DensityKernelKind kernel = DensityKernelKind::Warren;
  // The run's time step (integrator.dt) and the number density of its mobile particles (0 where not
  // known: a spec not yet validated), for a law's checks of its stability limits and neighbour count.
  double dt = 0;
  double number_density = 0;
};

// The density pass of a law with kDensity: its kernel when pair.kernel is not given (kDefaultKernel;
// Warren's where the law does not say) and each pair's kernel range (density_range(v); v.rd, the
// many-body range, where the law does not say).
template <class Law>
inline constexpr DensityKernelKind law_default_kernel = [] {
  if constexpr (requires { Law::kDefaultKernel; })
    return Law::kDefaultKernel;
  else
    return DensityKernelKind::Warren;
}();
// The kernels a law with kDensity accepts (kKernels; every kernel where it does not say).
template <class Law>
constexpr auto law_kernels() {
  if constexpr (requires { Law::kKernels; })
    return Law::kKernels;
  else
    return std::array<DensityKernelKind, 3>{DensityKernelKind::Warren, DensityKernelKind::Lucy,
                                            DensityKernelKind::Wendland};
}
template <class Law>
double law_density_range(const PairValues& v) {
  if constexpr (requires { Law::density_range(v); })
    return Law::density_range(v);
  else
    return v.rd;
}

// The species keys of a law (kSpeciesOwn: per-species values such as eDPD's heat capacity, written in
// [[species]] blocks); none where the law declares none.
template <class Law>
constexpr auto law_species_keys() {
  if constexpr (requires { Law::kSpeciesOwn; })
    return Law::kSpeciesOwn;
  else
    return std::array<LawKey, 0>{};
}

// A check a law makes on one resolved pair: the key it is about and why (the schema adds the key's full
// name, its value and the species pair).
struct LawProblem {
  std::string_view key;
  const char* why = nullptr;  // nullptr: no problem
  double other = 0;           // a value the message quotes
};

// A law's warning about one resolved pair (Law::warning; none where the law has no such hook), in the
// form of a LawProblem: the run goes on, `mesodpd run` and `mesodpd check` print it.
template <class Law>
LawProblem law_warning(const PairValues& v) {
  if constexpr (requires { Law::warning(v); })
    return Law::warning(v);
  else
    return {};
}

}  // namespace mesodpd
