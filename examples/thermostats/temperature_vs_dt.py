#!/usr/bin/env python3
"""Temperature error against the time step for every integrator of mesodpd (issue 27, "Temperature
against dt"): Groot-Warren at lambda = 0.5 and 0.65, and the pairwise thermostats Lowe-Andersen,
Shardlow S1, Peters and Stoyanov-Groot after a conservative velocity-Verlet step.

The fluid is the standard one of examples/thermostats/*.toml: rho = 3, a = 25, gamma = 4.5 (Gamma = 4.5
for Lowe-Andersen; Gamma = 0.5 and alpha = 4.5 for Stoyanov-Groot), kT = 1, box 12^3, N = 5184. Each run starts from the config's random placement,
relaxes for --equil time units and then samples the kinetic temperature sum m v^2 / (3N - 3) of
thermo.csv every 0.1 time units (every step where dt > 0.1) for --time time units. The error bar is the
standard error of --blocks block means.

Usage:
  temperature_vs_dt.py [--mesodpd build/mesodpd] [--out out/thermostats] [--jobs 2]
                       [--time 60] [--equil 10] [--dts 0.01 0.02 ...] [--schemes "Lowe-Andersen" ...]
                       [--plot docs/thermostats_temperature_vs_dt.png]
Writes OUT/temperature_vs_dt.csv and prints the markdown table of docs/validation.md.
"""
import argparse
import concurrent.futures
import math
import os
import pathlib
import re
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent

# (label, config, lambda or None)
SCHEMES = [
    ("Groot-Warren lambda = 0.5", "groot_warren.toml", 0.5),
    ("Groot-Warren lambda = 0.65", "groot_warren.toml", 0.65),
    ("Lowe-Andersen", "lowe_andersen.toml", None),
    ("Shardlow S1", "shardlow.toml", None),
    ("Peters", "peters.toml", None),
    ("Stoyanov-Groot", "stoyanov_groot.toml", None),
]


def config_text(path, dt, steps, every, lam):
    text = path.read_text()
    text = re.sub(r"(?m)^dt = .*$", f"dt = {dt}", text)
    text = re.sub(r"(?m)^steps = .*$", f"steps = {steps}", text)
    text = re.sub(r"(?m)^thermo_every = .*$", f"thermo_every = {every}", text)
    if lam is not None:
        text = re.sub(r"(?m)^lambda = .*$", f"lambda = {lam}", text)
    return text


def one_run(args, label, cfg, lam, dt):
    name = f"{pathlib.Path(cfg).stem}{'' if lam is None else '_l' + str(lam)}_dt{dt}"
    run_dir = pathlib.Path(args.out) / name
    run_dir.mkdir(parents=True, exist_ok=True)
    every = max(1, round(0.1 / dt))
    equil_steps = round(args.equil / dt)
    steps = equil_steps + round(args.time / dt)
    toml = run_dir / "run.toml"
    toml.write_text(config_text(HERE / cfg, dt, steps, every, lam))
    thermo = run_dir / "out" / "thermo.csv"
    if not (thermo.exists() and last_step(thermo) == steps):
        subprocess.run([args.mesodpd, "run", str(toml), "--out", str(run_dir / "out"), "--threads", "1"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    temps = []
    with open(thermo) as f:
        header = f.readline().strip().split(",")
        col = header.index("temperature")
        for line in f:
            row = line.strip().split(",")
            if int(row[0]) > equil_steps:
                temps.append(float(row[col]))
    mean, err = block_mean(temps, args.blocks)
    return {"scheme": label, "dt": dt, "steps": steps, "samples": len(temps), "kT": mean, "err": err}


def last_step(thermo):
    with open(thermo) as f:
        lines = f.read().strip().splitlines()
    return int(lines[-1].split(",")[0]) if len(lines) > 1 else -1


def block_mean(x, blocks):
    n = len(x) // blocks
    means = [sum(x[b * n:(b + 1) * n]) / n for b in range(blocks)]
    m = sum(means) / blocks
    var = sum((v - m) ** 2 for v in means) / (blocks - 1)
    return m, math.sqrt(var / blocks)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesodpd", default="build/mesodpd")
    ap.add_argument("--out", default="out/thermostats")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--time", type=float, default=60.0, help="production time units per run")
    ap.add_argument("--equil", type=float, default=10.0, help="relaxation time units before sampling")
    ap.add_argument("--blocks", type=int, default=10)
    ap.add_argument("--dts", type=float, nargs="+", default=[0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.08, 0.1])
    ap.add_argument("--plot", default="", help="write the figure here (matplotlib)")
    ap.add_argument("--schemes", nargs="+", default=[], help="run only these labels (default: all)")
    args = ap.parse_args()
    schemes = [s for s in SCHEMES if not args.schemes or s[0] in args.schemes]
    tasks = [(label, cfg, lam, dt) for label, cfg, lam in schemes for dt in args.dts]
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        results = list(pool.map(lambda t: one_run(args, *t), tasks))
    out = pathlib.Path(args.out)
    with open(out / "temperature_vs_dt.csv", "w") as f:
        f.write("scheme,dt,steps,samples,kT,err\n")
        for r in results:
            f.write(f"{r['scheme']},{r['dt']},{r['steps']},{r['samples']},{r['kT']:.6f},{r['err']:.6f}\n")
    # One table: rows dt, columns schemes, deviation from kT = 1 in per cent with its error.
    labels = [s[0] for s in schemes]
    print("| dt | " + " | ".join(labels) + " |")
    print("|---|" + "---|" * len(labels))
    for dt in args.dts:
        cells = []
        for label in labels:
            r = next(r for r in results if r["scheme"] == label and r["dt"] == dt)
            cells.append(f"{100 * (r['kT'] - 1):+.2f} +- {100 * r['err']:.2f}%")
        print(f"| {dt} | " + " | ".join(cells) + " |")
    print()
    for label in labels:
        ok = [r["dt"] for r in results if r["scheme"] == label and abs(r["kT"] - 1) <= 0.01]
        held = 0.0
        for dt in args.dts:  # the largest dt up to which every dt held 1%
            if dt in ok:
                held = dt
            else:
                break
        print(f"{label}: within 1% up to dt = {held}")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=100)
        for label, marker in zip(labels, "osD^vP"):
            rs = [r for r in results if r["scheme"] == label]
            ax.errorbar([r["dt"] for r in rs], [100 * (r["kT"] - 1) for r in rs], yerr=[100 * r["err"] for r in rs],
                        marker=marker, capsize=2, label=label)
        ax.axhspan(-1, 1, color="0.9", zorder=0)
        ax.axhline(0, color="0.5", lw=0.8)
        ax.axvline(0.06, color="0.7", lw=0.8, ls="--")
        ax.set_yscale("symlog", linthresh=1.0, linscale=1.0)  # linear within +-1%, logarithmic beyond
        ax.set_xlabel("time step dt")
        ax.set_ylabel("kinetic temperature error (%), symlog")
        ax.set_title("rho = 3, a = 25, gamma = Gamma = 4.5 (S-G: Gamma = 0.5, alpha = 4.5), N = 5184", fontsize=10)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot)
        print(f"wrote {args.plot}", file=sys.stderr)


if __name__ == "__main__":
    main()
