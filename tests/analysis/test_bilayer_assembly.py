#!/usr/bin/python3
# examples/amphiphiles/bilayer_assembly.py without a simulation, in a few seconds: the random start
# (particle count, molecules, every bond at r0 = 0.5 under the minimum image, random bond directions,
# every bead inside the box, the angles of each molecule: along the chains, none across the branch point, Osprey-DPD's
# lipid only H-T-T and T-T-T) and the membrane measures: bilayer.py's pre-assembled bilayer (as
# placed, with random displacements, and turned so that its normal is x) is a bilayer; the random
# starts, the bilayer with a stalk through the water, a cylinder and a spherical micelle are not; the lamellar peaks count 1, 4 and 13 directions.
# usage: test_bilayer_assembly.py SOURCE_DIR
import os
import sys
import tempfile

import numpy as np

from checks import check, finish  # tests/analysis/checks.py

source = sys.argv[1]
sys.path.insert(0, os.path.join(source, "tools"))
sys.path.insert(0, os.path.join(source, "examples", "amphiphiles"))
import bilayer as B  # noqa: E402
import bilayer_assembly as A  # noqa: E402


tmp = tempfile.mkdtemp(prefix="bilayer_assembly_")
rng = np.random.default_rng(3)

# 1. Topology of the two molecules.
mol = B.H3T4_2
sp = mol.species
check(len(mol) == 11 and len(mol.local_bonds) == 10 and len(mol.local_angles) == 9,
      f"H3(T4)2: {len(mol)} beads, {len(mol.local_bonds)} bonds, {len(mol.local_angles)} angles = 11, 10, 9")
check(all(not (sp[i] == "T" and sp[j] == "H" and sp[k] == "T") for i, j, k in mol.local_angles),
      "H3(T4)2: no T-H-T angle across the branch point")
o = B.OSPREY_LIPID
pat = sorted({"".join(o.species[i] for i in t) for t in o.local_angles})
check(len(o) == 15 and len(o.local_bonds) == 14 and len(o.local_angles) == 10 and pat == ["HTT", "TTT"],
      f"Osprey lipid: {len(o)} beads, {len(o.local_bonds)} bonds, angles {len(o.local_angles)} of {pat}")
check(sorted(i for p, i in o.local_bonds if p == 1) == [2, 8], "Osprey lipid: the second head carries a tail and the third head")
check((A.slab_width(mol), A.slab_width(o)) == (5.0, 7.0), f"slab widths {A.slab_width(mol)}, {A.slab_width(o)} = 5, 7")

# 2. The random start: counts, bonds, box.
for name, m, box, n_mol in (("set A, a = 1.05 box", mol, A.box_for(0, 1.05, 128, 3000), 128),
                            ("set A, cube 10", mol, (10.0, 10.0, 10.0), 192),
                            ("Osprey, cube 10", o, (10.0, 10.0, 10.0), 120)):
    path = os.path.join(tmp, "rs.data")
    A.random_start(path, box, n_mol, 3000, 7, m)
    pos, species, mids, bx, bonds = A.read_lammps_data(path)
    d = pos[bonds[:, 0]] - pos[bonds[:, 1]]
    d -= np.asarray(bx) * np.round(d / np.asarray(bx))
    r = np.linalg.norm(d, axis=1)
    check(len(pos) == 3000 and len(np.unique(mids[mids > 0])) == n_mol and np.sum(mids > 0) == n_mol * len(m)
          and len(bonds) == n_mol * len(m.local_bonds),
          f"{name}: {len(pos)} particles, {len(np.unique(mids[mids > 0]))} molecules, {len(bonds)} bonds")
    check(np.all(np.abs(r - 0.5) < 1e-6), f"{name}: bond lengths {r.min():.8f} .. {r.max():.8f} = 0.5")
    check(np.all(pos >= 0) and np.all(pos < np.asarray(bx)), f"{name}: every bead inside the box")
    # Random orientations: the mean bond direction is near zero (each component's standard error
    # is about 0.58 / sqrt(bonds), 0.013 here; 0.06 is more than four of them).
    mean_dir = np.abs((d / r[:, None]).mean(axis=0)).max()
    check(mean_dir < 0.06, f"{name}: mean bond direction {mean_dir:.3f} < 0.06")
    met = A.metrics(pos, species, mids, bx, A.slab_width(m))
    check(not met["bilayer"] and met["lamellar_peaks"] == 0,
          f"{name}: the random start is no bilayer (slab excess {met['slab_' + met['normal']]:.2f}, "
          f"lamellar peaks {met['lamellar_peaks']})")

# 3. The pre-assembled bilayer, as placed, displaced and turned.
path = os.path.join(tmp, "pre.data")
B.write_data(path, 8, 1.05, 3000, 5, mol)
pos, species, mids, bx, _ = A.read_lammps_data(path)
w = A.slab_width(mol)
for what, p, b in (("as placed", pos, bx),
                   ("displaced by 0.3 (Gaussian, each axis)", pos + rng.normal(0, 0.3, pos.shape), bx),
                   ("turned: normal x", pos[:, [2, 0, 1]], (bx[2], bx[0], bx[1]))):
    met = A.metrics(p, species, mids, b, w)
    check(met["bilayer"] == 1 and met["normal"] == ("x" if "turned" in what else "z") and met["lamellar_peaks"] == 1
          and met["water_core"] < 0.05,
          f"pre-assembled {what}: bilayer {met['bilayer']}, normal {met['normal']}, slab excess "
          f"{met['slab_' + met['normal']]:.2f}, coverage {met['coverage']:.2f}, water in core {met['water_core']:.3f}")

# The same bilayer with a stalk: a column (radius 1) of tail beads of its molecules across the water.
lz = bx[2]
k = np.flatnonzero(species == "W")[:150]
p = pos.copy()
r, phi = np.sqrt(rng.uniform(0, 1, 150)), rng.uniform(0, 2 * np.pi, 150)
p[k] = np.stack([4 + r * np.cos(phi), 4 + r * np.sin(phi), 0.5 * lz + 3.0 + rng.uniform(0, lz - 6.0, 150)], 1) % bx
s2, m2 = species.copy(), mids.copy()
s2[k], m2[k] = "T", 1 + np.arange(150) % 128
met = A.metrics(p, s2, m2, bx, w)
check(met["bilayer"] == 0 and met["tail_water"] > 0.05 and met["coverage"] == 1.0,
      f"pre-assembled with a stalk: bilayer {met['bilayer']}, tails in the water layer {met['tail_water']:.3f}")

# 4. A cylinder along y and a spherical micelle (molecules along radii, tails inside, in water).
def radial(n_mol, directions, centres, box):
    pos, species, mids = [], [], []
    for k in range(n_mol):
        u, c = directions[k], centres[k]
        for j, s in enumerate("TTTTHHH"):
            pos.append(c + (0.25 + 0.5 * j) * u)
            species.append(s)
            mids.append(k + 1)
    n_w = 3000 - len(pos)
    pos += list(rng.uniform(0, 1, (n_w, 3)) * box)
    species += ["W"] * n_w
    mids += [0] * n_w
    return np.mod(np.array(pos), box), np.array(species), np.array(mids)


box = np.array([10.0, 10.0, 10.0])
phi = rng.uniform(0, 2 * np.pi, 150)
dirs = np.stack([np.cos(phi), np.zeros(150), np.sin(phi)], axis=1)
cents = np.stack([np.full(150, 5.0), rng.uniform(0, 10, 150), np.full(150, 5.0)], axis=1)
met = A.metrics(*radial(150, dirs, cents, box), tuple(box), 5.0)
check(met["bilayer"] == 0 and met["coverage"] < 0.6 and met["lamellar_peaks"] == 4,
      f"cylinder along y: bilayer {met['bilayer']}, coverage {met['coverage']:.2f}, lamellar peaks {met['lamellar_peaks']}")
u = rng.normal(size=(60, 3))
u /= np.linalg.norm(u, axis=1)[:, None]
met = A.metrics(*radial(60, u, np.tile([5.0, 5.0, 5.0], (60, 1)), box), tuple(box), 5.0)
check(met["bilayer"] == 0 and met["coverage"] < 0.3 and met["lamellar_peaks"] == 13,
      f"spherical micelle: bilayer {met['bilayer']}, coverage {met['coverage']:.2f}, lamellar peaks {met['lamellar_peaks']}")

finish()
