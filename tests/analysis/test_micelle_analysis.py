#!/usr/bin/python3
# examples/amphiphiles/micelles.py's aggregate analysis on hand-made data, under a second: the
# tail-contact clusters of a periodic box (one aggregate straddling the boundary, one in the middle,
# a free molecule, tails closer than 1 only through the minimum image); the counting of exits and
# entries between micelles and free solution; the free fraction, the number- and molecule-weighted
# mean aggregation numbers and the size distribution of a known series of frames.
# usage: test_micelle_analysis.py SOURCE_DIR
import importlib.util
import os
import sys

import numpy as np

from checks import check, finish  # tests/analysis/checks.py

source = sys.argv[1]
sys.path.insert(0, os.path.join(source, "tools"))
spec = importlib.util.spec_from_file_location("micelles", os.path.join(source, "examples", "amphiphiles", "micelles.py"))
mic = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mic)


# 1. Clusters from tail contacts. Molecules of one head (H) and two tail beads (T), box 10.
box = 10.0
pos, mol, tail = [], [], []


def molecule(m, tails, head):
    for p in tails:
        pos.append(p), mol.append(m), tail.append(True)
    pos.append(head), mol.append(m), tail.append(False)


molecule(1, [(0.2, 5.0, 5.0), (0.6, 5.0, 5.0)], (1.0, 5.0, 5.0))  # across x = 0 from molecule 2
molecule(2, [(9.7, 5.0, 5.0), (9.3, 5.0, 5.0)], (8.9, 5.0, 5.0))
molecule(3, [(9.5, 5.8, 5.0), (9.5, 6.2, 5.0)], (9.5, 6.6, 5.0))  # touches molecule 2
molecule(4, [(5.0, 5.0, 5.0), (5.4, 5.0, 5.0)], (5.8, 5.0, 5.0))
molecule(5, [(5.0, 5.9, 5.0), (5.0, 6.3, 5.0)], (5.0, 6.7, 5.0))  # 0.9 from molecule 4
molecule(6, [(5.0, 5.0, 8.2), (5.0, 5.0, 8.6)], (5.0, 5.0, 6.2))  # heads do not count: free
pos.append((2.0, 2.0, 2.0)), mol.append(0), tail.append(False)  # a water bead
sizes, label, mols = mic.aggregates(np.array(pos), np.array(mol), np.array(tail), box)
per_mol = {m: int(sizes[label[k]]) for k, m in enumerate(mols)}
check(per_mol == {1: 3, 2: 3, 3: 3, 4: 2, 5: 2, 6: 1}, f"aggregate of each molecule {per_mol}")
check(sorted(sizes.tolist()) == [1, 2, 3], f"aggregate sizes {sorted(sizes.tolist())} = [1, 2, 3]")

# 2. Exits and entries: molecule sizes per frame (frames x 4 molecules), micelles of >= 2.
z = np.array([[3, 3, 3, 1],
              [2, 2, 1, 1],   # molecule 3 leaves (exit)
              [2, 2, 1, 1],
              [4, 4, 4, 4],   # molecules 3 and 4 enter
              [4, 4, 4, 4]])
exits, entries = mic.exchange_events(z, 2)
check((exits, entries) == (1, 2), f"exits {exits} = 1, entries {entries} = 2")

# 3. Equilibrium statistics of frames with known answers (one block per frame).
z = np.array([[3, 3, 3, 1, 1, 2, 2, 1],    # micelles (>= 2): 3 and 2; free 3 of 8
              [4, 4, 4, 4, 2, 2, 1, 1],    # micelles 4 and 2; free 2 of 8
              [8, 8, 8, 8, 8, 8, 8, 8]])   # one micelle of 8; free 0
stats, dist = mic.equilibrium(np.array([0, 1, 2]), z, 100.0, 2, 3)
check(abs(stats["free_fraction"][0] - (3 + 2 + 0) / 24) < 1e-12, f"free fraction {stats['free_fraction'][0]} = 5/24")
check(abs(stats["free_concentration"][0] - (5 / 3) / 100.0) < 1e-12,
      f"free concentration {stats['free_concentration'][0]} = (5/3)/100")
check(abs(stats["micelles_per_frame"][0] - 5 / 3) < 1e-12, f"micelles per frame {stats['micelles_per_frame'][0]} = 5/3")
want_n = (5 / 2 + 6 / 2 + 8 / 1) / 3
check(abs(stats["number_average_aggregation"][0] - want_n) < 1e-12,
      f"number-average aggregation {stats['number_average_aggregation'][0]} = {want_n}")
want_w = ((9 + 4) / 5 + (16 + 4) / 6 + 8) / 3
check(abs(stats["weight_average_aggregation"][0] - want_w) < 1e-12,
      f"molecule-weighted aggregation {stats['weight_average_aggregation'][0]} = {want_w}")
p = {s: v for s, v, e in dist}
check(abs(p[1] - 5 / 24) < 1e-12 and abs(p[2] - 4 / 24) < 1e-12 and abs(p[3] - 3 / 24) < 1e-12
      and abs(p[4] - 4 / 24) < 1e-12 and abs(p[8] - 8 / 24) < 1e-12 and abs(sum(p.values()) - 1) < 1e-12,
      f"molecule-weighted distribution {p}")
check((stats["exits"], stats["entries"], stats["molecules_ever_free"]) == (1, 4, 4),
      f"exits {stats['exits']}, entries {stats['entries']}, ever free {stats['molecules_ever_free']}")

finish()
