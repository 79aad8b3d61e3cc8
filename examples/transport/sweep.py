#!/usr/bin/env python3
"""A slice of seed 000 Table 1 measured: D, eta and Sc of a DPD fluid at gamma = 4.5, rho = 4, kT = 1
for a few weight exponents s and dissipative cutoffs r_c (seed 000 Eq. 8), against the table's
kinetic-theory formulas (g(r) = 1).

Each point is examples/transport/transport.toml with s, r_d (the table's r_c), dt and the sampling
changed; `mesodpd run` writes transport.json (D by Green-Kubo and by Einstein, the Green-Kubo eta, Sc,
their block errors) and this script gathers them into the markdown table of docs/validation.md
("Transport coefficients"). A point whose transport.json exists for the same config is not rerun.

The time step shrinks with the friction: the kinetic-theory friction rate of a particle is kT / (m D)
with D from Table 1, and dt is chosen so that rate x dt is about 0.1 (the Groot-Warren integrator's
temperature drifts beyond that); the window of the correlations is ~20-30 friction times or more.

Usage:
  sweep.py [--mesodpd build/mesodpd] [--out out/transport] [--jobs 1] [--a 0] [--points 0 1 ...]
           [--blocks 10] [--scale 1.0] [--threads 1]
--scale multiplies the block length (0.2 for a quick look with larger errors).
"""
import argparse
import concurrent.futures
import json
import math
import pathlib
import platform
import re
import subprocess

HERE = pathlib.Path(__file__).resolve().parent

# (s, r_c, box, dt, every, lags, stress_lags, block steps): D's window = lags x every x dt, eta's
# stress_lags x every x dt; an origin of the VACF and MSD every 5th sample. The large cutoffs have 3-7
# times the pairs of r_c = 1 and need a 4-6 times smaller dt, so they run in a 6^3 box (still 3.2 r_c
# wide) for fewer time units. Their eta is almost all the lag-0 spike of the dissipative and random
# stress; the rest of the stress correlation (the kinetic part) decays as exp(-2 t / tau_v), tau_v ~ D,
# so eta's window is ~3-5 tau_v there: a longer one only adds noise (docs/validation.md).
POINTS = [
    (2.0, 1.0, 8.0, 0.04, 1, 100, 50, 2500),     # windows 4 and 2,       block 100 time units
    (1.0, 1.0, 8.0, 0.02, 1, 100, 50, 5000),     # windows 2 and 1,       block 100
    (0.5, 1.0, 8.0, 0.01, 2, 100, 50, 10000),    # windows 2 and 1,       block 100
    (0.5, 1.5, 6.0, 0.0025, 2, 100, 30, 4000),   # windows 0.5 and 0.15,  block 10
    (0.5, 1.88, 6.0, 0.0015, 2, 100, 15, 4000),  # windows 0.3 and 0.045, block 6
]


def table1(s, rc, gamma=4.5, rho=4.0, kT=1.0):
    """Seed 000 Table 1 (and Eq. 16): D, eta = rho D / 2 + eta_D, Sc = eta / (rho D) for unit mass."""
    d = 3 * kT * (s + 1) * (s + 2) * (s + 3) / (8 * math.pi * gamma * rho * rc**3)
    bracket = 1 / (s + 1) - 4 / (s + 2) + 6 / (s + 3) - 4 / (s + 4) + 1 / (s + 5)
    eta_d = 2 * math.pi * gamma * rho**2 * rc**5 / 15 * bracket
    eta = rho * d / 2 + eta_d
    return d, eta, eta / (rho * d)


def table1_sc_as_printed(s, rc, gamma=4.5, rho=4.0, kT=1.0):
    """The Sc row exactly as the table prints it (1/2 + (c gamma rho r_c^4)^2 / (n kT))."""
    c, n = {2.0: (2 * math.pi, 70875), 1.0: (math.pi, 2025), 0.5: (2 * math.pi, 1999)}[s]
    return 0.5 + (c * gamma * rho * rc**4) ** 2 / (n * kT)


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def config_text(a, s, rc, box, dt, every, lags, stress_lags, block, blocks):
    text = (HERE / "transport.toml").read_text()
    text = re.sub(r"(?m)^box = [^#\n]*", f"box = [{box}, {box}, {box}]", text, count=1)
    start = block // 2 // every * every  # start-up: half a block, at least 20 friction times
    steps = start + blocks * block
    # Table 1's r_c is the cutoff of the dissipative and random forces (`rd`). The conservative force keeps
    # its cutoff 1 where it acts; at a = 0 it does not, and `rc` follows r_c so that the pair range is one
    # number.
    for key, value in [("a", a), ("rc", rc if a == 0 else 1.0), ("rd", rc), ("s", s), ("dt", dt), ("steps", steps),
                       ("start", start), ("every", every), ("lags", lags), ("stress_lags", stress_lags),
                       ("block", block)]:
        text = re.sub(rf"(?m)^{key} = [^#\n]*", f"{key} = {value}   ", text, count=1)
    return text


def one_point(args, k):
    s, rc, box, dt, every, lags, stress_lags, block = POINTS[k]
    block = max(2 * lags * every, int(round(block * args.scale / every)) * every)
    run_dir = pathlib.Path(args.out) / f"a{args.a:g}_s{s:g}_rc{rc:g}"
    run_dir.mkdir(parents=True, exist_ok=True)
    text = config_text(args.a, s, rc, box, dt, every, lags, stress_lags, block, args.blocks)
    toml = run_dir / "run.toml"
    result = run_dir / "out" / "transport.json"
    if not (result.exists() and toml.exists() and toml.read_text() == text):
        toml.write_text(text)
        log = run_dir / "run.log"
        with open(log, "w") as f:
            subprocess.run([args.mesodpd, "run", str(toml), "--out", str(run_dir / "out"), "--threads",
                            str(args.threads)], check=True, stdout=f, stderr=subprocess.STDOUT)
    return k, json.loads(result.read_text()), dt, block, box


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesodpd", default="build/mesodpd")
    ap.add_argument("--out", default="out/transport")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--a", type=float, default=0.0)
    ap.add_argument("--blocks", type=int, default=10)
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--points", type=int, nargs="*", default=list(range(len(POINTS))))
    args = ap.parse_args()

    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        done = sorted(pool.map(lambda k: one_point(args, k), args.points))

    print(f"a = {args.a:g}, gamma = 4.5, rho = 4, kT = 1, lambda = 0.5, {args.blocks} blocks; "
          f"{cpu_name()}, {args.threads} thread(s) per run")
    print()
    print("| s | r_c | box | dt | blocks x time | kT measured | D (MSD) | D (VACF) | D Table 1 | eta (Green-Kubo) "
          "| eta Table 1 | Sc measured | Sc Table 1 (formula as printed) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for k, j, dt, block, box in done:
        s, rc = POINTS[k][0], POINTS[k][1]
        d_t, eta_t, sc_t = table1(s, rc)
        pm = lambda key: f"{j[key]:.4g} +- {j[key + '_err']:.2g}"
        print(f"| {s:g} | {rc:g} | {box:g}^3 | {dt:g} | {j['blocks']} x {block * dt:g} | {j['kT']:.3f} "
              f"| {pm('d_msd')} | {pm('d_vacf')} | {d_t:.4g} | {pm('eta')} | {eta_t:.4g} "
              f"| {pm('schmidt')} | {sc_t:.4g} ({table1_sc_as_printed(s, rc):.4g}) |")
        rows.append({"s": s, "rc": rc, "box": box, "dt": dt, "block_steps": block, **j,
                     "d_table1": d_t, "eta_table1": eta_t, "sc_table1": sc_t})
    (pathlib.Path(args.out) / f"sweep_a{args.a:g}.json").write_text(json.dumps(rows, indent=2) + "\n")


if __name__ == "__main__":
    main()
