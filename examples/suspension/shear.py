#!/usr/bin/python3
"""The viscosity of a suspension of free rigid spheres under steady Lees-Edwards shear (issue 26).

Writes the config (base.toml, the box, rate and run length, and spheres of radius --radius placed at
random at the volume fraction --phi by examples/colloids/place_bodies.py; --phi 0 runs the fluid alone),
runs it unless --analyse, and reports two measurements of the viscosity:

* the total shear stress of the box (fluid and the bodies' molecular stress), eta = sigma_xy / rate,
  from lees_edwards's shear_summary.csv, and eta_r = eta / eta_0;
* the spheres' mean stresslet S_xy (bodies.csv, averaged over the rows after the start-up, block
  errors): in a suspension the particles add n <S_xy> to the stress (Batchelor 1970), so
  eta_r - 1 = n <S_xy> / (eta_0 rate), and the intrinsic viscosity [eta] = <S_xy> / (eta_0 rate V_s)
  with V_s = 4/3 pi a^3 for the radius a of --a-h (Einstein: 5/2); the stresslet radius
  a_S = (3 <S_xy> / (10 pi eta_0 rate))^(1/3), the radius of the continuum sphere with that stresslet.

    /usr/bin/python3 examples/suspension/shear.py --phi 0.02 --rate 0.02 --time 2000 --out out/susp-dilute
"""
import argparse
import csv
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def block_mean(values, blocks):
    n = len(values) // blocks
    if n == 0:
        return float("nan"), float("nan")
    means = [sum(values[k * n:(k + 1) * n]) / n for k in range(blocks)]
    m = sum(means) / blocks
    var = sum((x - m) ** 2 for x in means) / (blocks - 1)
    return m, math.sqrt(var / blocks)


def write_config(args, path):
    with open(os.path.join(HERE, "base.toml")) as f:
        text = f.read()
    steps = int(round(args.time / args.dt))
    start = int(round(args.start / args.dt))
    for old, new in [("box = [24, 24, 24]", f"box = [{args.box}, {args.box}, {args.box}]"),
                     ("seed = 61", f"seed = {args.seed}"), ("shear_rate = 0.05", f"shear_rate = {args.rate}"),
                     ("equilibrate = 2500", f"equilibrate = {start}"), ("dt = 0.02", f"dt = {args.dt}"),
                     ("steps = 25000", f"steps = {steps}")]:
        if old not in text:  # base.toml changed: say so rather than run the wrong config
            sys.exit(f"shear.py: '{old}' is not in base.toml")
        text = text.replace(old, new)
    if args.phi > 0:
        spheres = subprocess.run(
            ["/usr/bin/python3", os.path.join(ROOT, "examples", "colloids", "place_bodies.py"), "--box", str(args.box),
             "--radius", str(args.radius), "--phi", str(args.phi), "--seed", str(args.seed), "--gap", str(args.gap)],
            check=True, capture_output=True, text=True).stdout
        extra = f"output_every = {args.every}\n"
        if args.repulsion_range is not None:
            extra += f"repulsion_range = {args.repulsion_range}\n"
        spheres = spheres.replace('[[body]]\nsolid', '[[body]]\n' + extra + 'solid')
        text += "\n" + spheres
    with open(path, "w") as f:
        f.write(text)


def summary(folder):
    out = {}
    with open(os.path.join(folder, "shear_summary.csv")) as f:
        for r in csv.DictReader(f):
            out[r["quantity"]] = (float(r["value"]), float(r["error"]))
    return out


def stresslets(folder, start_step):
    """Per row step: the mean S_xy over the bodies (each row the mean over its interval)."""
    by_step = {}
    with open(os.path.join(folder, "bodies.csv")) as f:
        for r in csv.DictReader(f):
            s = int(r["step"])
            if s <= start_step:
                continue
            by_step.setdefault(s, []).append(float(r["sxy"]))
    steps = sorted(by_step)
    return [sum(by_step[s]) / len(by_step[s]) for s in steps], len(by_step[steps[0]]) if steps else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--phi", type=float, required=True, help="volume fraction of the solid spheres (0: fluid alone)")
    ap.add_argument("--rate", type=float, default=0.05)
    ap.add_argument("--time", type=float, default=500.0, help="run length (time units)")
    ap.add_argument("--start", type=float, default=50.0, help="start-up left out of the averages")
    ap.add_argument("--box", type=float, default=24.0)
    ap.add_argument("--radius", type=float, default=2.0, help="radius of the solid spheres")
    ap.add_argument("--gap", type=float, default=0.5, help="smallest surface gap of the random placement")
    ap.add_argument("--repulsion-range", type=float, default=None,
                    help="the bodies' contact repulsion_range (default: the [[body]] default, 0.5)")
    ap.add_argument("--a-h", type=float, default=2.0, help="hydrodynamic radius for [eta] (docs/validation.md 15)")
    ap.add_argument("--eta0", type=float, default=0.8593, help="the fluid's viscosity (reverse Poiseuille)")
    ap.add_argument("--dt", type=float, default=0.02)
    ap.add_argument("--every", type=int, default=50, help="steps between rows of bodies.csv")
    ap.add_argument("--seed", type=int, default=61)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--blocks", type=int, default=10)
    ap.add_argument("--out", required=True)
    ap.add_argument("--mesodpd", default=os.path.join(ROOT, "build", "mesodpd"))
    ap.add_argument("--analyse", action="store_true", help="only analyse an earlier run in --out")
    ap.add_argument("--fluid-tol", type=float, default=0.1, help="--check's tolerance on the fluid's part")
    ap.add_argument("--check", action="store_true",
                    help="assert (exit 1 otherwise) that the fluid's part of the stress, eta - n<S_xy>/rate, is eta_0 "
                         "within --fluid-tol (Batchelor: the particles add n<S>; without the bodies' virial eta_r would be "
                         "that part alone), and that eta_r lies between 1 + 2.5 phi + 2.6 phi^2 and twice "
                         "Krieger-Dougherty's (1 - phi/0.63)^-1.575, within two block errors")
    args = ap.parse_args()
    if not args.analyse:
        os.makedirs(args.out, exist_ok=True)
        cfg = os.path.join(args.out, "config.toml")
        write_config(args, cfg)
        subprocess.run([args.mesodpd, "run", cfg, "--out", args.out, "--threads", str(args.threads), "--no-progress"],
                       check=True, stdout=open(os.path.join(args.out, "log.txt"), "w"))
    s = summary(args.out)
    eta, eta_err = s["eta"]
    print(f"phi {args.phi} rate {args.rate}: eta = {eta:.4f} +- {eta_err:.4f}, eta_r = {eta / args.eta0:.4f} +- "
          f"{eta_err / args.eta0:.4f} (eta_0 = {args.eta0})")
    if args.phi > 0:
        start_step = int(round(args.start / args.dt))
        series, count = stresslets(args.out, start_step)
        sxy, sxy_err = block_mean(series, args.blocks)
        volume = args.box ** 3
        n = count / volume
        vs = 4.0 / 3.0 * math.pi * args.a_h ** 3
        intrinsic = sxy / (args.eta0 * args.rate * vs)
        a_s = (3.0 * sxy / (10.0 * math.pi * args.eta0 * args.rate)) ** (1.0 / 3.0) if sxy > 0 else float("nan")
        re_p = args.rate * args.a_h ** 2 * 3.0 / args.eta0
        print(f"  {count} spheres (phi_h = {n * vs:.4f} with a_h = {args.a_h}), Re_p = rate a^2 / nu = {re_p:.3f}: "
              f"<S_xy> = {sxy:.4f} +- {sxy_err:.4f} per sphere, [eta] = {intrinsic:.3f} +- "
              f"{sxy_err / (args.eta0 * args.rate * vs):.3f} (Einstein 2.5), stresslet radius a_S = {a_s:.3f}, "
              f"particle stress n<S_xy>/rate = {n * sxy / args.rate:.4f} +- {n * sxy_err / args.rate:.4f}")
        fluid = (eta - n * sxy / args.rate) / args.eta0
        phi = n * vs
        kd = (1.0 - phi / 0.63) ** (-2.5 * 0.63)
        print(f"  fluid part (eta - n<S_xy>/rate) / eta_0 = {fluid:.4f}; Krieger-Dougherty (phi_m 0.63) {kd:.4f}, "
              f"Batchelor-Green 1 + 2.5 phi + 6.2 phi^2 = {1 + 2.5 * phi + 6.2 * phi * phi:.4f}")
        if args.check:
            err = 2.0 * eta_err / args.eta0  # two block errors of eta_r
            ok = abs(fluid - 1.0) <= args.fluid_tol and 1.0 + 2.5 * phi + 2.6 * phi * phi - err <= eta / args.eta0 <= 2.0 * kd + err
            print("check:", "passed" if ok else "FAILED")
            if not ok:
                sys.exit(1)


if __name__ == "__main__":
    main()
