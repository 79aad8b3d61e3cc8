#!/usr/bin/python3
# Writes slab.data: a LAMMPS data file (atom_style atomic) with an A-rich slab |z - Lz/2| < Lz/4 in a
# B-rich surrounding, both at number density 3, placed at random, no velocities (the config draws them).
# usage: make_slab.py [OUT] [--box LX LY LZ] [--seed S]
import argparse
import random

parser = argparse.ArgumentParser()
parser.add_argument("out", nargs="?", default="slab.data")
parser.add_argument("--box", nargs=3, type=float, default=[8.0, 8.0, 24.0])
parser.add_argument("--density", type=float, default=3.0)
parser.add_argument("--seed", type=int, default=7)
args = parser.parse_args()
lx, ly, lz = args.box
n = round(args.density * lx * ly * lz)
rng = random.Random(args.seed)
atoms = []
for i in range(n):
    x, y, z = rng.uniform(0, lx), rng.uniform(0, ly), rng.uniform(0, lz)
    kind = 1 if abs(z - lz / 2) < lz / 4 else 2
    atoms.append((i + 1, kind, x, y, z))
with open(args.out, "w") as f:
    f.write("A-rich slab in B (examples/fields_slab/make_slab.py)\n\n")
    f.write(f"{n} atoms\n2 atom types\n\n")
    f.write(f"0 {lx} xlo xhi\n0 {ly} ylo yhi\n0 {lz} zlo zhi\n\n")
    f.write("Masses\n\n1 1.0\n2 1.0\n\nAtoms # atomic\n\n")
    for a in atoms:
        f.write(f"{a[0]} {a[1]} {a[2]:.6f} {a[3]:.6f} {a[4]:.6f}\n")
print(f"{args.out}: {n} particles, {sum(1 for a in atoms if a[1] == 1)} of type A")
