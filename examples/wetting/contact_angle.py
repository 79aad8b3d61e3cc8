#!/usr/bin/python3
"""Contact angle of a cylindrical sessile drop from a 2-D density map (an [analysis.fields] CSV with
bins along x and z only, averaged over y).

    /usr/bin/python3 examples/wetting/contact_angle.py OUT/map.csv [--wall 2.0] [--skip 1.0]

The liquid density rho_l is the median of the bins denser than half the map's 99th percentile; the
half-density contour (rho_l / 2; the vapour is empty) is traced with matplotlib, its points closer than
--skip to the wall (the layered liquid next to it) are dropped, and a circle is fitted to the rest
(algebraic fit, then geometric least squares). The contact angle, measured through the liquid, is where
that circle meets the wall plane z = --wall: cos(theta) = (z_wall - z_centre) / R.
Used by run.py; as a script it prints the angle of one map.
"""
import argparse
import json
import math
import sys

import numpy as np


def read_map(path):
    """(x centres, z centres, density[z, x]) of a fields CSV with one bin along y."""
    d = np.genfromtxt(path, delimiter=",", names=True)
    nx, nz = int(d["ix"].max()) + 1, int(d["iz"].max()) + 1
    if int(d["iy"].max()) != 0:
        raise SystemExit(f"{path}: needs one bin along y (a 2-D map in the xz-plane)")
    rho = np.nan_to_num(d["density"]).reshape(nz, nx)
    return d["x"][:nx].copy(), d["z"][::nx].copy(), rho


def liquid_density(rho):
    top = np.percentile(rho, 99)
    return float(np.median(rho[rho > 0.5 * top]))


def contour_points(x, z, rho, level):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots()
    cs = ax.contour(x, z, rho, levels=[level])
    segs = cs.allsegs[0]
    plt.close(fig)
    if not segs:
        return np.zeros((0, 2))
    return max(segs, key=len)  # the drop's outline (stray specks of vapour give short pieces)


def fit_circle(pts):
    """Algebraic (Kasa) fit, refined by minimising the geometric distances."""
    xs, zs = pts[:, 0], pts[:, 1]
    a = np.column_stack([xs, zs, np.ones_like(xs)])
    b = -(xs ** 2 + zs ** 2)
    (dd, ee, ff), *_ = np.linalg.lstsq(a, b, rcond=None)
    xc, zc = -dd / 2, -ee / 2
    r = math.sqrt(max(xc * xc + zc * zc - ff, 1e-12))
    try:
        from scipy.optimize import least_squares
        res = least_squares(lambda p: np.hypot(xs - p[0], zs - p[1]) - p[2], [xc, zc, r])
        xc, zc, r = res.x
    except ImportError:
        pass
    rms = float(np.sqrt(np.mean((np.hypot(xs - xc, zs - zc) - r) ** 2)))
    return float(xc), float(zc), float(abs(r)), rms


def contact_angle(x, z, rho, wall, skip):
    rho_l = liquid_density(rho)
    pts = contour_points(x, z, rho, 0.5 * rho_l)
    used = pts[pts[:, 1] > wall + skip] if len(pts) else pts
    out = {"rho_l": rho_l, "points": int(len(used))}
    if len(used) < 10:
        out.update({"theta": float("nan"), "note": "no drop outline found (a film, or no liquid)"})
        return out, pts, used
    xc, zc, r, rms = fit_circle(used)
    c = (wall - zc) / r
    out.update({"xc": xc, "zc": zc, "radius": r, "rms": rms,
                "theta": math.degrees(math.acos(c)) if abs(c) <= 1 else float("nan"),
                "base_width": 2 * math.sqrt(r * r - (wall - zc) ** 2) if abs(c) <= 1 else float("nan"),
                "height": zc + r - wall})
    return out, pts, used


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("csv")
    ap.add_argument("--wall", type=float, default=2.0, help="z of the wall surface")
    ap.add_argument("--skip", type=float, default=1.0, help="contour points below wall + skip are not fitted")
    args = ap.parse_args()
    out, _, _ = contact_angle(*read_map(args.csv), args.wall, args.skip)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    sys.exit(main())
