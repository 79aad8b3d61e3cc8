#!/usr/bin/python3
"""Steady conduction between a hot and a cold wall: eDPD's conductivity against kappa and the heat cutoff
(examples/heat/README.md, docs/validation.md 8d).

usage: conductivity.py [--mesodpd build/mesodpd] [--out out/heat] [--cases CVKAPPA:RCT ...] [--jobs 2]
                       [--steps N] [--png FILE] [--check] [--analyse-only]

Runs examples/heat/conduction.toml (C_v = 1000, walls at 1.1 and 0.9, 10 apart) once per case C_v kappa :
r_cT (default 0:1 1:1 3.6:1 10:1 30:1 1:1.5 3.6:1.5 10:1.5), each into OUT/cvk<C_v kappa>_rct<r_cT>, and
reads its flux.json and flux_profile.csv:

- at the middle plane (z = 6.5) the heat flux J and the gradient give k = -J / (dT/dz) and the thermal
  diffusivity D_T = k / (n C_v) (the run's own summary prints them);
- D_T of C_v kappa = 0 is the heat the particles carry by their own diffusion (no conduction between
  them): D_0. The conduction's share D_T - D_0 is compared with the mean-field (kinetic-theory) value
  2 pi n C_v kappa r_cT^5 / 315 (s_T = 2, docs/physics.md "eDPD");
- the boundary layers: the profile fitted by a line over the bulk (3.5 < z < 9.5) and extrapolated to the
  wall surfaces z = 1.5 and 11.5 gives the fluid's own temperature difference; the walls' 0.2 less that is
  the two Kapitza jumps; the largest departure of a bin within 2 of a wall from the bulk line is the
  layer's extra deviation.

Writes OUT/conductivity.json and, with --png, D_T - D_0 against the mean field for both cutoffs. --check
exits 1 unless every run's middle-plane flux lies between the two walls' (within 4 errors), D_0 lies
within 25% of the fluid's self-diffusion 0.30 (docs/validation.md 4 and 10: without conduction only the
particles' own motion carries heat), and, where its error is below 0.1, the conduction's share is between
0.3 and 1.1 of the mean field (docs/validation.md 8: a disordered fluid's pair network conducts 0.4-0.8
of it).
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import re
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "conduction.toml")
CV = 1000.0
N = 3.0


def case_dir(out, cvk, rct):
    return os.path.join(out, f"cvk{cvk:g}_rct{rct:g}")


def run(binary, out, cvk, rct, steps):
    d = case_dir(out, cvk, rct)
    os.makedirs(d, exist_ok=True)
    text = open(CONFIG).read()
    text = re.sub(r"^kappa = [0-9.e-]+", f"kappa = {cvk / CV:.8g}", text, count=1, flags=re.M)  # [pair]'s, not the walls'

    text = re.sub(r"^rct = [0-9.]+", f"rct = {rct:g}", text, flags=re.M)
    if steps:
        text = re.sub(r"^steps = \d+", f"steps = {steps}", text, flags=re.M)
        text = re.sub(r"^start = \d+", f"start = {steps * 5 // 13}", text, flags=re.M)
    cfg = os.path.join(d, "config.toml")
    with open(cfg, "w") as f:
        f.write(text)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    with open(os.path.join(d, "run.log"), "w") as log:
        subprocess.run([binary, "run", cfg, "--out", d], check=True, stdout=log, stderr=subprocess.STDOUT, env=env)
    return cvk, rct


def mean_field(cvk, rct):
    return 2 * math.pi * N * cvk * rct ** 5 / 315.0


def boundary(d):
    z, t = [], []
    with open(os.path.join(d, "flux_profile.csv")) as f:
        for row in csv.DictReader(f):
            if row["mean_temp"] not in ("nan", ""):
                z.append(float(row["position"]))
                t.append(float(row["mean_temp"]))
    z, t = np.array(z), np.array(t)
    bulk = (z > 3.5) & (z < 9.5)
    slope, icpt = np.polyfit(z[bulk], t[bulk], 1)
    line = slope * z + icpt
    near = ((z > 1.5) & (z < 3.5)) | ((z > 9.5) & (z < 11.5))
    dev = float(np.max(np.abs(t[near] - line[near]))) if near.any() else float("nan")
    t_hot, t_cold = slope * 1.5 + icpt, slope * 11.5 + icpt
    return {"fluid_dT": t_hot - t_cold, "jump_hot": 1.1 - t_hot, "jump_cold": t_cold - 0.9, "layer_deviation": dev,
            "bulk_slope": slope}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesodpd", default="build/mesodpd")
    ap.add_argument("--out", default="out/heat")
    ap.add_argument("--cases", nargs="+", default=["0:1", "1:1", "3.6:1", "10:1", "30:1", "1:1.5", "3.6:1.5", "10:1.5"])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--steps", type=int, default=0)
    ap.add_argument("--png")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--analyse-only", action="store_true")
    a = ap.parse_args()
    cases = [tuple(float(v) for v in c.split(":")) for c in a.cases]
    if not a.analyse_only:
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
            for f in concurrent.futures.as_completed([pool.submit(run, a.mesodpd, a.out, c, r, a.steps) for c, r in cases]):
                print("done C_v kappa = {:g}, r_cT = {:g}".format(*f.result()), flush=True)
    rows, ok = [], True
    d0 = None
    for cvk, rct in sorted(cases):
        d = case_dir(a.out, cvk, rct)
        j = json.load(open(os.path.join(d, "flux.json")))
        mid = j["planes"][1]
        walls = {w["species"]: w for w in j["walls"]}
        hot, cold = walls["hot"], walls["cold"]
        row = {"cv_kappa": cvk, "rct": rct, "flux": mid["flux"], "flux_err": mid["flux_err"],
               "convection": mid["convection"], "conductivity": mid["conductivity"],
               "conductivity_err": mid["conductivity_err"], "D_T": mid["diffusivity"], "D_T_err": mid["diffusivity_err"],
               "hot": hot["per_area"], "hot_err": hot["per_area_err"], "cold": cold["per_area"],
               "cold_err": cold["per_area_err"], "mean_field": mean_field(cvk, rct)}
        row.update(boundary(d))
        if cvk == 0:
            d0 = row["D_T"], row["D_T_err"]
        rows.append(row)
        lo = row["hot"] - 4 * math.hypot(row["hot_err"], row["flux_err"])
        hi = -row["cold"] + 4 * math.hypot(row["cold_err"], row["flux_err"])
        if not (lo <= row["flux"] <= hi):
            ok = False
            print(f"C_v kappa {cvk:g}, r_cT {rct:g}: the middle plane's flux {row['flux']:.4g} is not between the walls'")
    if d0 is None:
        sys.exit("conductivity.py: include the case 0:1 (no conduction: the particles' own heat transport D_0)")
    print(f"D_0 (C_v kappa = 0: heat carried by self-diffusion) = {d0[0]:.4f} +- {d0[1]:.4f}")
    print("C_v kappa  r_cT   J (middle)        k                D_T               (D_T - D_0) / mean field   Kapitza jumps   layer dev.")
    for r in rows:
        share = (r["D_T"] - d0[0]) / r["mean_field"] if r["mean_field"] > 0 else float("nan")
        share_err = math.hypot(r["D_T_err"], d0[1]) / r["mean_field"] if r["mean_field"] > 0 else float("nan")
        r["share"], r["share_err"] = share, share_err
        print(f"{r['cv_kappa']:8g} {r['rct']:5g}  {r['flux']:7.3f} +- {r['flux_err']:.3f}  {r['conductivity']:7.1f} +- "
              f"{r['conductivity_err']:5.1f}  {r['D_T']:.4f} +- {r['D_T_err']:.4f}  {share:6.3f} +- {share_err:.3f} "
              f"(mean field {r['mean_field']:.4f})   {r['jump_hot']:+.4f} {r['jump_cold']:+.4f}   {r['layer_deviation']:.4f}")
        if r["mean_field"] > 0 and share_err < 0.1 and not (0.3 < share < 1.1):
            ok = False
            print(f"C_v kappa {r['cv_kappa']:g}, r_cT {r['rct']:g}: the conduction's share {share:.3f} is outside (0.3, 1.1)")
    if not (0.225 < d0[0] < 0.375):
        ok = False
        print(f"D_0 = {d0[0]:.4f} is not within 25% of the self-diffusion 0.30")
    json.dump({"D_0": d0[0], "D_0_err": d0[1], "runs": rows}, open(os.path.join(a.out, "conductivity.json"), "w"), indent=2)
    if a.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        for rct, marker in ((1.0, "o"), (1.5, "s")):
            sel = [r for r in rows if r["rct"] == rct and r["mean_field"] > 0]
            if sel:
                ax.errorbar([r["mean_field"] for r in sel], [r["D_T"] - d0[0] for r in sel],
                            yerr=[math.hypot(r["D_T_err"], d0[1]) for r in sel], fmt=marker, label=f"r_cT = {rct:g}")
        m = max(r["mean_field"] for r in rows)
        ax.plot([0, m], [0, m], "k--", label="mean field")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("mean-field D = 2 pi n C_v kappa r_cT^5 / 315")
        ax.set_ylabel("measured D_T - D_0")
        ax.set_title("eDPD conduction between walls (C_v = 1000)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(a.png, dpi=110)
        print(f"wrote {a.png}")
    if a.check and not ok:
        sys.exit(1)


if __name__ == "__main__":
    main()
