#!/usr/bin/python3
"""Checks tools/chain_analysis.py (run by ChainAnalysis.GsdTrajectoryHoldsTheTopologyAndIsMeasured in tests/physics/test_bonds.cpp).

1. Synthetic rods with known answers: straight rods of N beads at spacing b rotating rigidly in the
   xy plane at angular speed w: R_g^2 = b^2 (N^2 - 1) / 12, R_e^2 = ((N - 1) b)^2, every bond b long,
   every bond angle 0, C_e(t) = cos(w t) (tau_e = arccos(1/e) / w), centre of mass at rest (D = 0).
2. With a mesodpd GSD file as argument: its bonds/ and angles/ chunks and the mol ids are consistent
   (bonded beads share a molecule id) and the script runs on it, writing its CSV files and plot.
usage: check_chain_analysis.py SCRIPT_DIR WORK_DIR [FILE.gsd EXPECTED_BONDS EXPECTED_ANGLES]
"""
import math
import os
import sys

import numpy as np


def fail(msg):
    print("check_chain_analysis: " + msg, file=sys.stderr)
    sys.exit(1)


def near(name, got, want, tol):
    if not abs(got - want) <= tol:
        fail(f"{name} = {got}, expected {want} (tolerance {tol})")


def main():
    script_dir, work = sys.argv[1], sys.argv[2]
    sys.path.insert(0, script_dir)
    import chain_analysis as ca
    import gsd.hoomd

    os.makedirs(work, exist_ok=True)
    n_mol, beads, b, w, dt = 3, 5, 0.5, 0.1, 1.0
    n = n_mol * beads
    path = os.path.join(work, "rods.gsd")
    with ca.open_gsd(gsd.hoomd, path, "w") as f:
        for step in range(60):
            fr = gsd.hoomd.Frame() if hasattr(gsd.hoomd, "Frame") else gsd.hoomd.Snapshot()
            fr.configuration.step = step
            fr.configuration.box = [20, 20, 20, 0, 0, 0]
            fr.particles.N = n
            fr.particles.types = ["A"]
            fr.particles.typeid = np.zeros(n, dtype=np.uint32)
            pos = np.zeros((n, 3))
            phi = w * step * dt
            for m in range(n_mol):
                centre = np.array([-5.0 + 5 * m, 0.0, 0.0])
                for k in range(beads):
                    s = (k - (beads - 1) / 2) * b
                    pos[m * beads + k] = centre + s * np.array([math.cos(phi), math.sin(phi), 0.0])
            fr.particles.position = pos
            fr.particles.image = np.zeros((n, 3), dtype=np.int32)
            if step == 0:
                fr.bonds.N = n_mol * (beads - 1)
                fr.bonds.types = ["spring"]
                fr.bonds.typeid = np.zeros(fr.bonds.N, dtype=np.uint32)
                fr.bonds.group = [[m * beads + k, m * beads + k + 1] for m in range(n_mol) for k in range(beads - 1)]
                fr.angles.N = n_mol * (beads - 2)
                fr.angles.types = ["bend"]
                fr.angles.typeid = np.zeros(fr.angles.N, dtype=np.uint32)
                fr.angles.group = [[m * beads + k, m * beads + k + 1, m * beads + k + 2]
                                   for m in range(n_mol) for k in range(beads - 2)]
            fr.log["particles/mol"] = np.repeat(np.arange(1, n_mol + 1, dtype=np.int32), beads)
            f.append(fr)
    res = ca.analyse(path, dt)
    if list(res) != ["A5"]:
        fail(f"kinds {list(res)}, expected ['A5']")
    r = res["A5"]
    near("molecules", r["molecules"], 3, 0)
    near("<Rg^2>", r["rg2"][0], b * b * (beads**2 - 1) / 12, 1e-5)
    near("<Re^2>", r["re2"][0], ((beads - 1) * b) ** 2, 1e-5)
    near("bond length", float(np.mean(r["bond_lengths"])), b, 1e-5)
    near("bond angle (degrees)", float(np.max(r["angles"])), 0.0, 0.01)
    near("C_e(10)", r["c_e"][10], math.cos(w * 10 * dt), 1e-5)
    near("tau_e", r["tau_e"], math.acos(math.exp(-1)) / w, 0.05)
    near("D_com", r["d"], 0.0, 1e-12)
    ca.write(res, os.path.join(work, "rods"))
    for name in ("chains_summary.csv", "chains_timeseries.csv", "bond_length_distribution.csv",
                 "angle_distribution.csv"):
        if not os.path.getsize(os.path.join(work, "rods", name)):
            fail(f"{name} is empty")
    print("check_chain_analysis: synthetic rods OK")

    if len(sys.argv) > 3:
        gpath, want_bonds, want_angles = sys.argv[3], int(sys.argv[4]), int(sys.argv[5])
        with ca.open_gsd(gsd.hoomd, gpath, "r") as t:
            f0 = t[0]
            if f0.bonds.N != want_bonds or f0.angles.N != want_angles:
                fail(f"{gpath}: {f0.bonds.N} bonds and {f0.angles.N} angles, expected {want_bonds} and {want_angles}")
            if len(t) > 1 and t[1].bonds.N not in (0, want_bonds):
                fail("later frames disagree on bonds/N")
        import gsd.fl
        with ca.open_gsd(gsd.fl, gpath, "r") as raw:
            mol = raw.read_chunk(0, "log/particles/mol")
        group = np.asarray(f0.bonds.group)
        if np.any(mol[group[:, 0]] != mol[group[:, 1]]) or np.any(mol[group[:, 0]] <= 0):
            fail("a bond joins beads of different molecules")
        res = ca.analyse(gpath, 0.04)
        out = os.path.join(work, "run")
        ca.write(res, out)
        ca.plot(res, out)
        if not os.path.getsize(os.path.join(out, "chains.png")):
            fail("no plot")
        print(f"check_chain_analysis: {gpath}: kinds {sorted(res)} OK")


if __name__ == "__main__":
    main()
