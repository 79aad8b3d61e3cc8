#!/usr/bin/env python3
"""C_D against Re for the single pillar between plates (seed 004 Sect. 4.1, Fig. 8).

Reads the drag_summary.csv and drag.csv of one or more runs of pillar.toml (one body force each),
prints a table (Re, C_D with its block error, the momentum balance, the drift between the halves of
the averaging window) and draws C_D against Re with
  - the experiment for an unbounded cylinder quoted in seed 003 (Re 10/20/30/40 -> 2.93/2.08/1.76/1.58),
  - seed 004 Eq. 11 (C_D = 6/Re),
  - the continuum solution of the same confined geometry (lbm_reference.csv, when present).

Usage: /usr/bin/python3 examples/pillar/cd_re.py OUT_DIR [OUT_DIR ...] [--png FILE] [--body pillar]
"""
import argparse
import csv
import os
import sys

import numpy as np

EXPERIMENT = {10: 2.93, 20: 2.08, 30: 1.76, 40: 1.58}  # seed 003, table "Comparison of drag coefficients"


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def run_summary(out, body):
    rows = {r["body"]: r for r in read_rows(os.path.join(out, "drag_summary.csv"))}
    if body not in rows:
        sys.exit(f"{out}/drag_summary.csv: no body named {body!r} (bodies: {', '.join(rows)})")
    r = rows[body]
    total_fx = sum(float(x["fx"]) for x in rows.values())
    total_err = np.sqrt(sum(float(x["fx_err"]) ** 2 for x in rows.values()))
    # Drift: the drag and the fluid velocity in the first and second halves of the sampled window.
    d = np.genfromtxt(os.path.join(out, "drag.csv"), delimiter=",", names=True)
    half = len(d) // 2
    fx = d[f"{body}_fx"]
    vx = d["fluid_vx"]
    return {
        "out": out,
        "re": float(r["re"]),
        "cd": float(r["cd"]),
        "cd_err": float(r["cd_err"]),
        "u": float(r["fluid_vx"]),
        "drag": float(r["drag"]),
        "drag_err": float(r["drag_err"]),
        "walls_total": total_fx,
        "walls_total_err": total_err,
        "drift_f": fx[half:].mean() / fx[:half].mean() - 1,
        "drift_u": vx[half:].mean() / vx[:half].mean() - 1,
        "samples": int(r["samples"]),
    }


def lbm_reference(path):
    if not os.path.exists(path):
        return None
    rows = read_rows(path)
    if not rows:
        return None
    res = max(float(r["resolution"]) for r in rows)  # the finest grid
    rows = [r for r in rows if float(r["resolution"]) == res]
    re = np.array([float(r["re"]) for r in rows])
    cd = np.array([float(r["cd"]) for r in rows])
    order = np.argsort(re)
    return re[order], cd[order]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outs", nargs="+")
    ap.add_argument("--body", default="pillar")
    ap.add_argument("--png", default="pillar_cd_re.png")
    args = ap.parse_args()
    runs = sorted((run_summary(o, args.body) for o in args.outs), key=lambda r: r["re"])
    ref = lbm_reference(os.path.join(os.path.dirname(os.path.abspath(__file__)), "lbm_reference.csv"))
    print("run, Re, u, C_D, C_D err, C_D Re, C_D/continuum, all bodies F_x, drift F (2nd/1st half), drift u")
    for r in runs:
        ratio = ""
        if ref is not None and ref[0][0] <= r["re"] <= ref[0][-1]:
            # log-log interpolation of the continuum curve at this run's Re
            c = np.exp(np.interp(np.log(r["re"]), np.log(ref[0]), np.log(ref[1])))
            ratio = f"{r['cd'] / c:.3f}"
        print(f"{r['out']}, {r['re']:.3f}, {r['u']:.4f}, {r['cd']:.4g}, {r['cd_err']:.2g}, {r['cd'] * r['re']:.4g}, "
              f"{ratio}, {r['walls_total']:.5g} +- {r['walls_total_err']:.2g}, {100 * r['drift_f']:+.1f}%, "
              f"{100 * r['drift_u']:+.1f}%")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    re_line = np.logspace(-1, np.log10(50), 100)
    ax.loglog(re_line, 6 / re_line, "k:", label="seed 004 Eq. 11: $C_D = 6/Re$")
    ax.loglog(list(EXPERIMENT), list(EXPERIMENT.values()), "ks", mfc="none", label="experiment, unbounded (seed 003)")
    if ref is not None:
        ax.loglog(ref[0], ref[1], "b-", label="continuum (LBM), same confined geometry")
    ax.errorbar([r["re"] for r in runs], [r["cd"] for r in runs], yerr=[r["cd_err"] for r in runs], fmt="ro",
                label="mesodpd DPD, h = 30, d = 6")
    ax.set_xlabel("Re = rho u d / mu")
    ax.set_ylabel("C_D = 2 F_D / (rho u^2 A)")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.png, dpi=130)
    print(f"wrote {args.png}")


if __name__ == "__main__":
    main()
