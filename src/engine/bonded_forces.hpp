// Bonded forces: bonds, angles and dihedrals of the topology evaluated with the laws of
// physics/bond_laws.hpp. Partners are found by global id through an IdMap (owned or ghost), each term is
// evaluated once, by the rank that owns its first atom (bonds: the lower id; angles: the centre;
// dihedrals: the first atom of the central bond, b), and the forces
// are accumulated in fixed point, ghost contributions going back to their owners like pair forces, so
// the result is the same bits for any thread and rank count.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "core/box.hpp"
#include "core/id_map.hpp"
#include "core/pair_sums.hpp"
#include "core/particle_data.hpp"
#include "core/topology.hpp"
#include "parallel/halo.hpp"
#include "mesodpd/spec.hpp"
#include "physics/bond_laws.hpp"

namespace mesodpd {

// Why the bonded forces could not be evaluated: a FENE/WLC bond at or past its maximum extension, or a
// bond (or angle) whose partner the evaluating rank does not hold: it is farther away than the ghost
// layer reaches (at least `reach`; on one rank every partner is held).
struct BondProblem {
  enum Kind : int { Broken = 0, TooLong = 1, AngleTooLong = 2, DihedralTooLong = 3 };
  Kind kind = Broken;
  std::uint64_t index = 0;  // bond, angle or dihedral index in the topology (0-based)
  double length = 0;        // the offending distance
};

// Removes the pair force of listed pairs (storage indices i, j at [2k], [2k + 1]) from `fixed` (3
// integers per stored particle) and adds the negated sums to `totals` (9 integers, as
// ForceCompute::subtract_pairs, which is what the simulation passes).
using PairSubtractor =
    std::function<void(std::span<const std::uint32_t> pairs, std::int64_t* fixed, std::int64_t* totals)>;

class BondedForces {
 public:
  BondedForces() = default;
  // `reach`: how far the ghost layer reaches at least (neighbour cells are at least that wide), for
  // messages. Ids in the topology must be at most `max_id`.
  // `exclude`: which bonded pairs lose their pair force (1-2: bonded; 1-3: also two bonds apart).
  BondedForces(Topology topology, std::vector<BondParams> bond_types, std::vector<AngleParams> angle_types,
               double reach, std::uint32_t max_id, BondExclusion exclude = BondExclusion::None,
               std::vector<DihedralParams> dihedral_types = {});

  bool empty() const { return topo_.empty(); }
  const Topology& topology() const { return topo_; }
  const std::vector<BondParams>& bond_types() const { return bond_types_; }
  const std::vector<AngleParams>& angle_types() const { return angle_types_; }
  const std::vector<DihedralParams>& dihedral_types() const { return dihedral_types_; }
  double reach() const { return reach_; }

  // Adds the bonded forces to p.f{x,y,z} of the local particles (the pair forces must be there) and,
  // with `with_sums`, their virial and energy to `sums` (summed over ranks). Collective over the halo's
  // ranks. Returns the problem with the smallest (kind, index) over all ranks, if any: then no force was
  // added.
  // With exclusions, `subtract` removes the pair force of the excluded pairs (each pair once, by the
  // rank that owns its lower id; a partner this rank does not hold is beyond the pair cutoff, so it
  // had no pair force).
  // With `fast` (multiple time stepping), the bonded force is written there instead (x, y, z per local
  // particle, ghost contributions included) and only the exclusions are added to p (the sums still
  // include both); with `only_fast` too, nothing else is done: no exclusion subtracted, no sum taken.
  std::optional<BondProblem> compute(ParticleData& p, const Box& box, Halo& halo, bool with_sums, PairSums& sums,
                                     const PairSubtractor& subtract = {}, std::vector<double>* fast = nullptr,
                                     bool only_fast = false);
  // Excluded pairs (lower id, higher id), for tests.
  std::size_t excluded_pairs() const { return excl_of_.size(); }
  // Whether the pair force between ids a and b is excluded (bonds.exclude).
  bool excluded(std::uint32_t a, std::uint32_t b) const;

  // Appends the virial terms (core/pair_sums.hpp) of every bond (one term), angle (two) and dihedral
  // (three: a, c and d against b) of the
  // topology, evaluated on the local particles of `p`, which must hold every bonded atom (the whole
  // system, as the analyses see it on the root). Serial, in topology order; their d (x) f add up to
  // the bonded virial that compute() adds to the pair sums. For [analysis.stress_profile].
  void virial_terms(const ParticleData& p, const Box& box, VirialTerms& out) const;

  // How often the storage-index lists were built by looking ids up (the rest followed a sort or were
  // reused): for tests.
  std::uint64_t list_rebuilds() const { return list_rebuilds_; }

 private:
  Topology topo_;
  std::vector<BondParams> bond_types_;
  std::vector<AngleParams> angle_types_;
  std::vector<DihedralParams> dihedral_types_;
  double reach_ = 0;
  // Bonds and angles evaluated by the owner of id u: entries [bond_start_[u], bond_start_[u + 1]) of
  // owned_bonds_ and the same for angles (owner: the centre atom), packed so that one owner's terms
  // share cache lines (the loop visits owners in storage order, so u jumps around).
  struct OwnedBond {
    std::uint32_t partner;  // the other atom's id
    std::uint32_t index;    // in topo_.bonds
    std::int32_t type;
    std::int32_t owner_first;  // 1 if the owner is the bond's atom a (d = r_a - r_b)
  };
  struct OwnedAngle {
    std::uint32_t a, c;  // end atoms' ids
    std::uint32_t index;
    std::int32_t type;
  };
  struct OwnedDihedral {
    std::uint32_t a, c, d;  // the other atoms' ids (the owner is b)
    std::uint32_t index;
    std::int32_t type;
  };
  std::vector<std::uint32_t> bond_start_, angle_start_, dihedral_start_;
  std::vector<OwnedBond> owned_bonds_;
  std::vector<OwnedAngle> owned_angles_;
  std::vector<OwnedDihedral> owned_dihedrals_;

  // The same terms in storage indices, grouped by the local owner i: bonds [lb_start_[i],
  // lb_start_[i + 1]) of lbonds_, angles likewise. Partners are storage indices (IdMap::kNotHere when
  // this rank holds no copy). Valid for list_source_ at list_generation_. Rebuilt from ids when the
  // particles changed otherwise than by a sort (ghosts, migration, resize), followed through the
  // permutation when a sort alone happened (a single domain sorts every step in cell mode, and the
  // particles barely move, so that pass is almost sequential where a lookup by id is a random read per
  // bond), reused as they are when nothing moved in storage (Verlet steps between rebuilds, inner
  // steps of multiple time stepping).
  // 8 bytes: the list is rewritten every step in cell mode. The bond's index in the topology, needed
  // only to report a problem, is that of the entry at the same place in the owner's owned_bonds_ range.
  struct LocalBond {
    std::uint32_t j;     // the other atom's storage index
    std::uint32_t meta;  // type << 1 | owner_first (1 if the owner is the bond's atom a: d = r_a - r_b)
  };
  struct LocalAngle {
    std::uint32_t ja, jc;  // end atoms' storage indices
    std::uint32_t index;
    std::int32_t type;
  };
  struct LocalDihedral {
    std::uint32_t ja, jc, jd;  // storage indices of a, c, d
    std::uint32_t index;
    std::int32_t type;
  };
  void prepare_lists(const ParticleData& p);
  void lists_from_ids(const ParticleData& p);
  void lists_through(const std::vector<std::uint32_t>& order);
  std::vector<std::uint32_t> lb_start_, la_start_, ld_start_, new_of_old_, spare_start_;
  std::vector<LocalBond> lbonds_, spare_bonds_;
  std::vector<LocalAngle> langles_, spare_angles_;
  std::vector<LocalDihedral> ldihedrals_, spare_dihedrals_;
  const ParticleData* list_source_ = nullptr;
  std::uint64_t list_generation_ = 0;
  bool list_has_ghosts_ = false;
  std::uint64_t list_rebuilds_ = 0;
  // Excluded pairs by their lower id u: partners excl_of_[excl_start_[u] .. excl_start_[u + 1]).
  std::vector<std::uint32_t> excl_start_, excl_of_;
  std::vector<std::uint32_t> excl_pairs_;  // storage index pairs of one evaluation
  IdMap ids_;
  std::vector<std::int64_t> fixed_;  // integer forces, 3 per stored particle
  bool fixed_zero_ = false;          // every entry of fixed_ is zero
};

}  // namespace mesodpd
