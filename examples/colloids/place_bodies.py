#!/usr/bin/python3
"""Writes [[solid]] and [[body]] blocks for spheres placed at random, without overlaps, at a volume
fraction: the lines to append to a config (each rigid body of mesodpd is one [[solid]] moved by one
[[body]], docs/config.md). Random sequential addition in the periodic box: a sphere is kept when its
surface is at least --gap from every other's (at the nearest image); after --attempts rejections in a row
the placement gives up and says how far it got (exit 2).

    /usr/bin/python3 examples/colloids/place_bodies.py --box 32 --radius 2 --phi 0.1 > spheres.toml
    cat base.toml spheres.toml > suspension.toml
"""
import argparse
import math
import random
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--box", required=True, help="box lengths: L or Lx,Ly,Lz (all axes periodic)")
    ap.add_argument("--radius", type=float, required=True)
    ap.add_argument("--phi", type=float, required=True, help="volume fraction of the spheres")
    ap.add_argument("--gap", type=float, default=0.5, help="smallest surface-to-surface distance")
    ap.add_argument("--species", default="W", help="the frozen species of the spheres' particles")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--attempts", type=int, default=100000, help="rejections in a row before giving up")
    ap.add_argument("--prefix", default="colloid", help="solid names: prefix0, prefix1, ...")
    args = ap.parse_args()
    box = [float(v) for v in args.box.split(",")]
    if len(box) == 1:
        box *= 3
    if len(box) != 3 or min(box) <= 0:
        sys.exit("--box: give L or Lx,Ly,Lz, all positive")
    if not (args.radius > 0):
        sys.exit("--radius: must be positive")
    if not (0 < args.phi < 0.6):
        sys.exit("--phi: must be in (0, 0.6)")
    if 4 * args.radius >= min(box):
        sys.exit(f"--radius: {args.radius} reaches a quarter of the smallest box length {min(box)} or more, which "
                 "mesodpd refuses for a body")
    volume = box[0] * box[1] * box[2]
    sphere = 4.0 / 3.0 * math.pi * args.radius ** 3
    count = max(1, round(args.phi * volume / sphere))
    reach = 2 * args.radius + args.gap
    rng = random.Random(args.seed)
    centres = []
    misses = 0
    while len(centres) < count:
        c = [rng.uniform(0, box[a]) for a in range(3)]
        ok = True
        for d in centres:
            r2 = 0.0
            for a in range(3):
                x = c[a] - d[a]
                x -= box[a] * round(x / box[a])
                r2 += x * x
            if r2 < reach * reach:
                ok = False
                break
        if ok:
            centres.append(c)
            misses = 0
        else:
            misses += 1
            if misses >= args.attempts:
                got = len(centres) * sphere / volume
                print(f"place_bodies: could not reach phi = {args.phi}: {len(centres)} of {count} spheres placed "
                      f"(phi = {got:.4f}) before {args.attempts} rejections in a row; lower --phi or --gap",
                      file=sys.stderr)
                sys.exit(2)
    print(f"# {count} spheres of radius {args.radius} at phi = {count * sphere / volume:.4f} (asked {args.phi}), "
          f"seed {args.seed}, surfaces at least {args.gap} apart")
    for k, c in enumerate(centres):
        name = f"{args.prefix}{k}"
        print(f'[[solid]]\nname = "{name}"\nspecies = "{args.species}"\nshape = "sphere"\n'
              f"center = [{c[0]:.6f}, {c[1]:.6f}, {c[2]:.6f}]\nradius = {args.radius}\n")
        print(f'[[body]]\nsolid = "{name}"\n')


if __name__ == "__main__":
    main()
