#!/usr/bin/env python3
"""Shear viscosity eta(shear rate) of a DPD fluid by steady Lees-Edwards shear ([lees_edwards]).

Each point is examples/shear/shear.toml with the shear rate, the conservative amplitude a, the time
step and the run length changed; `mesodpd run` writes shear_summary.csv (eta with its kinetic and pair
parts and block errors) and thermo.csv (the temperature across the flow), and this script gathers them
into the markdown table of docs/validation.md ("Lees-Edwards shear") and a plot.

The images move at most 0.1 r_c per step (rate x L x dt <= 0.1): dt = min(--dt, 0.1 / (rate L)).
The ideal gas (--a 0) checks the dissipative viscosity eta_D = 2 pi gamma rho^2 r_c^5 / 1575 of Groot
and Warren (seed 000 Table 1, s = 2) in the pair part.

Usage:
  sweep.py [--mesodpd build/mesodpd] [--out out/shear] [--rates 0.05 0.1 0.2 0.4 0.8] [--a 25]
           [--time 1000] [--dt 0.04] [--jobs 1] [--plot docs/shear_eta_vs_rate.png] [--check]

--check asserts the expected results of examples/shear/README.md (exit 1 otherwise): at a = 25 every
rate up to 0.2 gives eta within 3 errors + 3% of the reverse-Poiseuille value 0.8593; at a = 0 every
rate up to 0.5 gives the pair part within 3 errors + 2% of Groot and Warren's eta_D.
"""
import argparse
import concurrent.futures
import csv
import math
import pathlib
import platform
import re
import subprocess

HERE = pathlib.Path(__file__).resolve().parent


def config(rate, a, time, box=10.0, stress_every=5, dt_max=0.04, name="shear.toml"):
    dt = min(dt_max, 0.1 / (abs(rate) * box))
    steps = int(round(time / dt))
    equilibrate = int(round(20.0 / dt))
    text = (HERE / name).read_text()
    text = re.sub(r"(?m)^shear_rate = .*$", f"shear_rate = {rate!r}", text)
    text = re.sub(r"(?m)^a = .*$", f"a = {a!r}", text)
    text = re.sub(r"(?m)^dt = .*$", f"dt = {dt!r}", text)
    text = re.sub(r"(?m)^steps = .*$", f"steps = {steps + equilibrate}", text)
    text = re.sub(r"(?m)^equilibrate = \d+", f"equilibrate = {equilibrate}", text)
    text = re.sub(r"(?m)^stress_every = \d+", f"stress_every = {stress_every}", text)
    return text, dt


def summary(path):
    out = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            out[row["quantity"]] = (float(row["value"]), float(row["error"]))
    return out


def mean_temperature(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    half = rows[len(rows) // 2:]
    return sum(float(r["temperature_transverse"]) for r in half) / len(half)


def run_point(args, rate):
    text, dt = config(rate, args.a, args.time, dt_max=args.dt, name=args.config)
    stem = "" if args.config == "shear.toml" else pathlib.Path(args.config).stem + "_"
    out = pathlib.Path(args.out) / f"{stem}a{args.a:g}_rate{rate:g}_dt{dt:g}"
    out.mkdir(parents=True, exist_ok=True)
    cfg = out / "shear.toml"
    if not (cfg.exists() and cfg.read_text() == text and (out / "shear_summary.csv").exists()):
        cfg.write_text(text)
        r = subprocess.run([args.mesodpd, "run", str(cfg), "--out", str(out), "--threads", str(args.threads)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise SystemExit(f"{cfg}: mesodpd exited with {r.returncode}\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    s = summary(out / "shear_summary.csv")
    return rate, dt, s, mean_temperature(out / "thermo.csv")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesodpd", default="build/mesodpd")
    ap.add_argument("--out", default="out/shear")
    ap.add_argument("--rates", type=float, nargs="+", default=[0.05, 0.1, 0.2, 0.4, 0.8])
    ap.add_argument("--a", type=float, default=25.0)
    ap.add_argument("--time", type=float, default=1000.0, help="time units sampled per point")
    ap.add_argument("--dt", type=float, default=0.04, help="largest time step (smaller where the images need it)")
    ap.add_argument("--config", default="shear.toml", help="the config in examples/shear (melt.toml: the polymer melt; melt_sg.toml: the melt under Stoyanov-Groot)")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--plot", default="")
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        results = list(pool.map(lambda r: run_point(args, r), args.rates))
    eta_d = 2 * math.pi * 4.5 * 9.0 / 1575.0
    print(f"{args.config}: a = {args.a:g}, rho = 3, kT = 1, box 12 x 10 x 8 (gradient 10), {args.time:g} time units per point "
          f"({platform.processor() or platform.machine()})\n")
    print("| shear rate | dt | eta | eta kinetic | eta pairs | N1 | N2 | kT across the flow |")
    print("|---|---|---|---|---|---|---|---|")
    for rate, dt, s, kt in results:
        e, k, p, n1, n2 = s["eta"], s["eta_kinetic"], s["eta_pairs"], s["N1"], s["N2"]
        print(f"| {rate:g} | {dt:.4g} | {e[0]:.4f} +- {e[1]:.4f} | {k[0]:.4f} +- {k[1]:.4f} | "
              f"{p[0]:.4f} +- {p[1]:.4f} | {n1[0]:.4f} +- {n1[1]:.4f} | {n2[0]:.4f} +- {n2[1]:.4f} | {kt:.4f} |")
    if args.a == 0:
        print(f"\nGroot-Warren eta_D = 2 pi gamma rho^2 r_c^5 / 1575 = {eta_d:.4f}")
    failed = []
    if args.check:
        for rate, _, s, _ in results:
            if args.config != "shear.toml":
                continue
            if args.a == 25 and rate <= 0.2:
                value, err, target = s["eta"][0], s["eta"][1], 0.8593
            elif args.a == 0 and rate <= 0.5:
                value, err, target = s["eta_pairs"][0], s["eta_pairs"][1], eta_d
            else:
                continue
            ok = abs(value - target) <= 3 * err + (0.03 if args.a == 25 else 0.02) * target
            print(f"check rate {rate:g}: {value:.4f} +- {err:.4f} against {target:.4f}: {'ok' if ok else 'FAILED'}")
            if not ok:
                failed.append(rate)
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax, bx) = plt.subplots(1, 2, figsize=(9, 3.6))
        rates = [r[0] for r in results]
        for key, label in (("eta", "total"), ("eta_kinetic", "kinetic"), ("eta_pairs", "pairs")):
            ax.errorbar(rates, [r[2][key][0] for r in results], yerr=[r[2][key][1] for r in results],
                        marker="o", capsize=3, label=label)
        ax.set_xscale("log")
        ax.set_xlabel("shear rate")
        ax.set_ylabel("viscosity")
        ax.legend()
        for key in ("N1", "N2"):
            bx.errorbar(rates, [r[2][key][0] for r in results], yerr=[r[2][key][1] for r in results],
                        marker="o", capsize=3, label=key)
        bx.axhline(0, color="grey", lw=0.5)
        bx.set_xscale("log")
        bx.set_xlabel("shear rate")
        bx.set_ylabel("normal stress difference")
        bx.legend()
        what = "simple fluid"
        if args.config.startswith("melt"):
            what = "polymer melt (10-bead chains)" + (", Stoyanov-Groot" if "_sg" in args.config else "")
        fig.suptitle(f"Lees-Edwards shear, {what}, a = {args.a:g}, rho = 3")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"\nwrote {args.plot}")
    if failed:
        raise SystemExit(f"checks failed at rates {failed}")


if __name__ == "__main__":
    main()
