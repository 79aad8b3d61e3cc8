#!/usr/bin/python3
# examples/pillar/lbm_reference.py (the lattice-Boltzmann continuum reference for the confined pillar)
# on small lattices, a few seconds: the empty channel started from rest reaches the plane Poiseuille
# profile; the mirror-half channel gives the same drag as the whole channel; the forces on plates and
# cylinder balance the body force in steady state; bad arguments are refused (non-zero exit, message).
# usage: test_lbm_reference.py SOURCE_DIR
import importlib.util
import math
import os
import subprocess
import sys

import numpy as np

from checks import check, finish  # tests/analysis/checks.py

source = sys.argv[1]
path = os.path.join(source, "examples", "pillar", "lbm_reference.py")
spec = importlib.util.spec_from_file_location("lbm_reference", path)
lbm = importlib.util.module_from_spec(spec)
spec.loader.exec_module(lbm)


# 1. empty channel h = 20 nodes from rest at fixed g: U = g h^2 / (12 nu) (node average: midpoint rule)
for nu in (1.0 / 6.0, 0.5):
    ch = lbm.Channel(4, cylinder=False, symmetric=False, nx=2)
    h = ch.nz_full
    g = 12 * nu * 0.02 / h ** 2
    s = lbm.Solver(ch, nu, g)
    s.set_equilibrium(np.ones((ch.nx, ch.nz)), np.zeros((ch.nx, ch.nz)), np.zeros((ch.nx, ch.nz)))
    for _ in range(int(20 * h ** 2 / (math.pi ** 2 * nu))):
        u, fp, fc = s.step()
    z = np.arange(ch.nz) + 0.5
    node_err = np.abs(s.macros()[1][0] / (g * z * (h - z) / (2 * nu)) - 1).max()
    check(node_err < 1e-6, "Poiseuille nodal profile, nu = %.3f: max relative error %.1e < 1e-6" % (nu, node_err))
    rel = abs(u / (g * h ** 2 / (12 * nu)) - 1)
    check(rel < 0.005, "Poiseuille mean velocity, nu = %.3f: relative error %.1e < 0.5%%" % (nu, rel))
    check(abs(fp / (g * ch.n_fluid) - 1) < 1e-6, "plates carry the whole body force: %.8f" % (fp / (g * ch.n_fluid)))

# 2. pillar at N = 4 nodes per diameter, Re = 5: half channel with mirror plane == whole channel
logs = []
half, _ = lbm.solve(lbm.Channel(4, symmetric=True), 5.0, 0.03, log=logs.append)
full, _ = lbm.solve(lbm.Channel(4, symmetric=False), 5.0, 0.03, log=logs.append)
print("\n".join(logs))
for r in (half, full):
    check(r["rel_change_u"] < 1e-5, "%s channel steady: relative change of U %.1e < 1e-5" % (r["domain"], r["rel_change_u"]))
    check(r["balance_residual"] < 1e-5, "%s channel: body force = plate + cylinder force within %.1e"
          % (r["domain"], r["balance_residual"]))
    check(0.2 < r["f_cylinder_fraction"] < 0.8, "%s channel: cylinder takes %.3f of the body force"
          % (r["domain"], r["f_cylinder_fraction"]))
check(abs(half["cd"] / full["cd"] - 1) < 1e-4, "mirror half vs whole channel C_D: %.6f vs %.6f" % (half["cd"], full["cd"]))
check(abs(half["re"] - 5.0) < 1e-3, "target Re reached: %.5f" % half["re"])

# 3. bad arguments: one clear message, non-zero exit
for bad, word in ((["--res", "5"], "even"), (["--re", "-1"], "positive")):
    p = subprocess.run(["/usr/bin/python3", path] + bad + ["--out", os.devnull], capture_output=True, text=True)
    check(p.returncode != 0 and word in p.stderr, "%s refused (exit %d): %s" % (" ".join(bad), p.returncode, p.stderr.strip()))

finish()
