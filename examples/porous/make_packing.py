#!/usr/bin/python3
"""Writes a 2-D voxel image (PGM) of a random packing of non-overlapping discs for examples/porous.

usage: make_packing.py OUT.pgm [--size LX LY] [--voxel H] [--radius R] [--porosity P] [--gap G]
                       [--depth D] [--seed S]

Random sequential addition: disc centres are drawn uniformly in the LX x LY rectangle, one after the
other, and a disc is kept only if its surface stays at least G from every disc already kept (periodic
distances, so discs wrap around the edges and the image tiles the plane). It stops at the number of
discs that gives the porosity P (solid fraction 1 - P with the exact disc areas), or fails if the
packing jams every time it is tried (a jammed packing is started again). G sets the narrowest pore throat (in r_c); 2 R must be at least D (walls.depth,
the largest cutoff), or the fluid would interact through a disc.

The image has LX / H columns (x) and LY / H rows (y); a pixel is solid (value 1) when its centre lies
inside a disc, fluid (0) otherwise, the format `[[solid]] shape = "image"` reads (docs/config.md
"Image files"): plain-text PGM ("P2", maxval 1), the first row written is the top of the picture (the
largest y), the last row is y = 0. Extruded along z it is a random array of parallel fibres.

The same arguments and seed give the same file, byte for byte (numpy's PCG64 generator). A summary
(discs, solid fraction of the discs and of the pixels, narrowest gap) goes to OUT.json.
"""
import argparse
import json
import math
import sys

import numpy as np


def fail(message):
    print(f"make_packing.py: error: {message}", file=sys.stderr)
    sys.exit(1)


def periodic_distance(a, b, box):
    d = np.abs(a - b)
    d = np.minimum(d, box - d)
    return np.hypot(d[..., 0], d[..., 1])


def pack(box, radius, count, gap, rng, max_tries, attempts):
    """Random sequential addition; a packing that jams (max_tries draws without placing the next disc)
    is thrown away and started again, up to `attempts` times."""
    for attempt in range(1, attempts + 1):
        centres = np.empty((0, 2))
        misses = 0
        while len(centres) < count and misses < max_tries:
            c = rng.random(2) * box
            if len(centres) == 0 or periodic_distance(centres, c, box).min() >= 2 * radius + gap:
                centres = np.vstack([centres, c])
                misses = 0
            else:
                misses += 1
        if len(centres) == count:
            return centres, attempt
    fail(f"jammed {attempts} times ({max_tries} draws without room for the next disc of {count}): "
         "ask for a higher porosity, a smaller gap or a larger box")


def rasterise(box, voxel, radius, centres):
    nx, ny = (int(round(L / voxel)) for L in box)
    x = (np.arange(nx) + 0.5) * voxel
    y = (np.arange(ny) + 0.5) * voxel
    px, py = np.meshgrid(x, y)  # [row = iy, column = ix]
    solid = np.zeros((ny, nx), dtype=np.uint8)
    for c in centres:
        dx = np.abs(px - c[0])
        dx = np.minimum(dx, box[0] - dx)
        dy = np.abs(py - c[1])
        dy = np.minimum(dy, box[1] - dy)
        solid[dx * dx + dy * dy < radius * radius] = 1
    return solid


def write_pgm(path, solid, comment):
    ny, nx = solid.shape
    with open(path, "w") as f:
        f.write("P2\n")
        for line in comment:
            f.write(f"# {line}\n")
        f.write(f"{nx} {ny}\n1\n")
        for row in solid[::-1]:  # top of the picture (largest y) first
            f.write(" ".join("1" if v else "0" for v in row) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--size", nargs=2, type=float, default=[40.0, 40.0], metavar=("LX", "LY"))
    ap.add_argument("--voxel", type=float, default=0.25)
    ap.add_argument("--radius", type=float, default=2.5)
    ap.add_argument("--porosity", type=float, default=0.7)
    ap.add_argument("--gap", type=float, default=1.5)
    ap.add_argument("--depth", type=float, default=1.0)
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--max-tries", type=int, default=100_000)
    ap.add_argument("--attempts", type=int, default=100)
    a = ap.parse_args()

    box = np.array(a.size)
    for L in box:
        if abs(L / a.voxel - round(L / a.voxel)) > 1e-9:
            fail(f"--size {L} is not a multiple of --voxel {a.voxel}")
    if not 0 < a.porosity < 1:
        fail(f"--porosity {a.porosity} must lie in (0, 1)")
    if 2 * a.radius < a.depth:
        fail(f"--radius {a.radius}: discs thinner than --depth {a.depth}, fluid would interact through them")
    if a.gap < 0:
        fail(f"--gap {a.gap} must be >= 0")
    if box.min() < 2 * a.radius + a.gap:
        fail(f"--size {a.size} too small for one disc of radius {a.radius} with gap {a.gap}")
    count = int(round((1 - a.porosity) * box.prod() / (math.pi * a.radius ** 2)))
    if count < 1:
        fail(f"--porosity {a.porosity} leaves no disc")

    rng = np.random.default_rng(a.seed)
    centres, attempts = pack(box, a.radius, count, a.gap, rng, a.max_tries, a.attempts)
    solid = rasterise(box, a.voxel, a.radius, centres)

    d = np.array([[periodic_distance(ci, cj, box) for cj in centres] for ci in centres])
    np.fill_diagonal(d, np.inf)
    summary = {
        "size": box.tolist(), "voxel": a.voxel, "pixels": [solid.shape[1], solid.shape[0]],
        "radius": a.radius, "gap": a.gap, "seed": a.seed, "discs": len(centres), "attempts": attempts,
        "solid_fraction_discs": len(centres) * math.pi * a.radius ** 2 / box.prod(),
        "solid_fraction_pixels": float(solid.mean()),
        "narrowest_gap": float(d.min() - 2 * a.radius) if len(centres) > 1 else None,
        "centres": centres.round(6).tolist(),
    }
    comment = [f"make_packing.py --size {a.size[0]:g} {a.size[1]:g} --voxel {a.voxel:g} --radius {a.radius:g} "
               f"--porosity {a.porosity:g} --gap {a.gap:g} --seed {a.seed}",
               f"{len(centres)} discs, solid fraction {summary['solid_fraction_pixels']:.4f} (pixels); "
               "1 = solid, 0 = fluid; bottom row at y = 0"]
    write_pgm(a.out, solid, comment)
    stem = a.out[:-4] if a.out.endswith(".pgm") else a.out
    with open(stem + ".json", "w") as f:
        json.dump(summary, f, indent=1)
        f.write("\n")
    print(f"{a.out}: {solid.shape[1]} x {solid.shape[0]} pixels, {len(centres)} discs of radius {a.radius}, "
          f"solid fraction {summary['solid_fraction_discs']:.4f} (discs) {summary['solid_fraction_pixels']:.4f} "
          f"(pixels), narrowest gap {summary['narrowest_gap']:.3f}")


if __name__ == "__main__":
    main()
