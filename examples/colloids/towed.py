#!/usr/bin/python3
"""The hydrodynamic radius of a rigid sphere of frozen particles ([[body]]), twice: from its drag when
towed (Stokes, F = 6 pi eta a U, with Hasimoto's correction for the periodic box) and from its torque
when turned (T = 8 pi eta a^3 Omega). Runs towed.toml at the speeds given and a turned copy of it, or
reads the outputs of earlier runs (--analyse), and writes towed.json.

Towed: the fluid carries a body force g that balances the drag, so that in the steady state the drag is
N m |g| exactly, whatever the fluid's mean velocity u_f; the sphere's velocity relative to the fluid is
U - <u_f> (u_f from thermo.csv's momentum). The sphere's own force (bodies.csv) must average to the
same N m |g|: that checks the body's force accounting (pair forces and bounce-backs). a_t solves
    zeta K(a_t / L) = 6 pi eta a_t,   zeta = N m |g| / (U - <u_f>),
    K(x) = 1 - 1.7601 c^(1/3) + c - 1.5593 c^2,  c = (4 pi / 3) x^3      (Hasimoto 1959, simple cubic).
The error of <u_f> is sqrt(2 kT / (zeta T)) over a sampled time T (the fluid's mean velocity relaxes
only through the sphere's friction, in M_f / zeta, ~260 time units here).
Turned: a_r = (T / (8 pi eta Omega))^(1/3) (the periodic images change T by O((a/L)^3), ~1%, neglected).

    /usr/bin/python3 examples/colloids/towed.py --mesodpd build/mesodpd --out out/towed --check
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def hasimoto(x):
    c = 4.0 * math.pi / 3.0 * x ** 3
    return 1.0 - 1.7601 * c ** (1.0 / 3.0) + c - 1.5593 * c * c


def block_mean(values, blocks):
    n = len(values) // blocks
    means = [sum(values[k * n:(k + 1) * n]) / n for k in range(blocks)]
    m = sum(means) / blocks
    err = math.sqrt(sum((x - m) ** 2 for x in means) / (blocks * (blocks - 1)))
    return m, err


def run(args, toml_text, name):
    folder = os.path.join(args.out, name)
    os.makedirs(folder, exist_ok=True)
    config = os.path.join(folder, "config.toml")
    with open(config, "w") as f:
        f.write(toml_text)
    cmd = [args.mesodpd, "run", config, "--out", folder, "--no-progress", "--threads", str(args.threads)]
    if args.steps:
        cmd += ["--steps", str(args.steps)]
    return subprocess.Popen(cmd, stdout=open(os.path.join(folder, "log.txt"), "w"), stderr=subprocess.STDOUT)


def mobile_count(folder):
    text = open(os.path.join(folder, "log.txt")).read()
    total = int(re.search(r"mesodpd [^:]*: (\d+) particles", text).group(1))
    frozen = int(re.search(r"body\[0\] '[^']*': (\d+) particles", text).group(1))
    return total - frozen


def rows(path, start):
    with open(path) as f:
        return [r for r in csv.DictReader(f) if int(r["step"]) > start]


def towed_result(folder, speed, g, eta, box, start, blocks, dt):
    n = mobile_count(folder)
    body = rows(os.path.join(folder, "bodies.csv"), start)
    thermo = rows(os.path.join(folder, "thermo.csv"), start)
    force, force_err = block_mean([-float(r["fx"]) for r in body], blocks)
    fluid, fluid_err = block_mean([float(r["momentum_x"]) / n for r in thermo], blocks)
    drag = n * abs(g)
    relative = speed - fluid
    zeta = drag / relative
    # The fluid's mean velocity wanders as a whole (variance kT / M_f) and relaxes only through the
    # sphere's friction, in M_f / zeta (~260 time units here, longer than the blocks): the error of its
    # mean over a time T is sqrt(2 kT / (zeta T)) whatever M_f, which the block error underestimates.
    sampled = (int(thermo[-1]["step"]) - start) * dt
    fluid_err = max(fluid_err, math.sqrt(2.0 * 1.0 / (zeta * sampled)))
    zeta_err = zeta * fluid_err / relative
    lo, hi = 0.1, box / 3.0  # zeta K(a/L) - 6 pi eta a decreases through zero in a
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if zeta * hasimoto(mid / box) - 6 * math.pi * eta * mid > 0:
            lo = mid
        else:
            hi = mid
    a = 0.5 * (lo + hi)
    # d/da [zeta K - 6 pi eta a] = zeta K' / L - 6 pi eta; error of a from that of zeta.
    dk = (hasimoto((a + 1e-6) / box) - hasimoto((a - 1e-6) / box)) / 2e-6
    a_err = abs(zeta_err * hasimoto(a / box) / (zeta * dk / box - 6 * math.pi * eta))
    return {"speed": speed, "mobile_particles": n, "drag_balance": drag, "body_force": force, "body_force_err": force_err,
            "fluid_velocity": fluid, "fluid_velocity_err": fluid_err, "relative_speed": relative,
            "reynolds_a": 3.0 * relative * a / eta, "a_t": a, "a_t_err": a_err, "hasimoto_K": hasimoto(a / box)}


def turned_result(folder, omega, eta, start, blocks):
    body = rows(os.path.join(folder, "bodies.csv"), start)
    torque, err = block_mean([-float(r["tz"]) for r in body], blocks)
    a = (torque / (8 * math.pi * eta * omega)) ** (1.0 / 3.0)
    return {"omega": omega, "torque": torque, "torque_err": err, "a_r": a, "a_r_err": a * err / (3 * torque)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesodpd", default="build/mesodpd")
    ap.add_argument("--out", default="out/towed")
    ap.add_argument("--speeds", default="0.075,0.15", help="towing speeds, comma separated")
    ap.add_argument("--omega", type=float, default=0.3)
    ap.add_argument("--eta", type=float, default=0.8674, help="the fluid's viscosity (docs/validation.md section 4)")
    ap.add_argument("--steps", type=int, default=0, help="steps of each run (0: the config's)")
    ap.add_argument("--start", type=int, default=8000, help="steps left out as the start-up")
    ap.add_argument("--blocks", type=int, default=8)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--analyse", action="store_true", help="read the outputs of earlier runs")
    ap.add_argument("--check", action="store_true", help="fail unless a_t and a_r agree within 10%% and the body's force is the balance's")
    ap.add_argument("--short", action="store_true",
                    help="CI: U = 0.15 only, 24,000 steps (4,000 start-up); fail unless a_t and a_r are each within "
                         "15%% of the long runs' 2.00 and 1.91 (docs/validation.md section 15)")
    args = ap.parse_args()
    if args.short:
        args.speeds, args.steps, args.start = "0.15", 24000, 4000
    base = open(os.path.join(HERE, "towed.toml")).read()
    box = 16.0
    speeds = [float(s) for s in args.speeds.split(",")]
    jobs = []
    for u in speeds:
        # The balancing body force: the drag expected for a_t ~ 1.9 over the mobile particles (~12,170).
        g = -6 * math.pi * args.eta * 1.9 * u / hasimoto(1.9 / box) / 12170
        text = base.replace("velocity = [0.15, 0, 0]", f"velocity = [{u}, 0, 0]").replace(
            "body_force = [-7.0e-4, 0, 0]", f"body_force = [{g:.6e}, 0, 0]")
        jobs.append(("towed_%g" % u, text, u, g))
    turned = base.replace("velocity = [0.15, 0, 0]", f"angular_velocity = [0, 0, {args.omega}]").replace(
        "body_force = [-7.0e-4, 0, 0]", "body_force = [0, 0, 0]")
    runs = [(name, text) for name, text, _, _ in jobs] + [("turned", turned)]
    if not args.analyse:
        pending = list(runs)
        active = []
        while pending or active:
            while pending and len(active) < args.jobs:
                name, text = pending.pop(0)
                active.append((name, run(args, text, name)))
            name, proc = active.pop(0)
            if proc.wait() != 0:
                sys.exit(f"run {name} failed: see {os.path.join(args.out, name, 'log.txt')}")
    result = {"eta": args.eta, "towed": [], "turned": None}
    for name, text, u, g in jobs:
        result["towed"].append(towed_result(os.path.join(args.out, name), u, g, args.eta, box, args.start, args.blocks, 0.04))
    result["turned"] = turned_result(os.path.join(args.out, "turned"), args.omega, args.eta, args.start, args.blocks)
    a_r = result["turned"]["a_r"]
    for t in result["towed"]:
        t["a_t_over_a_r"] = t["a_t"] / a_r
    with open(os.path.join(args.out, "towed.json"), "w") as f:
        json.dump(result, f, indent=2)
    for t in result["towed"]:
        print(f"towed U = {t['speed']}: drag N|g| = {t['drag_balance']:.4f}, body's force {t['body_force']:.4f} +- "
              f"{t['body_force_err']:.4f}; fluid u = {t['fluid_velocity']:.5f} +- {t['fluid_velocity_err']:.5f}; "
              f"Re_a = {t['reynolds_a']:.2f}; K = {t['hasimoto_K']:.3f}; a_t = {t['a_t']:.3f} +- {t['a_t_err']:.3f}")
    r = result["turned"]
    print(f"turned Omega = {r['omega']}: torque {r['torque']:.3f} +- {r['torque_err']:.3f}; a_r = {r['a_r']:.3f} +- {r['a_r_err']:.3f}")
    for t in result["towed"]:
        print(f"a_t / a_r = {t['a_t_over_a_r']:.3f} at U = {t['speed']}")
    if args.check:
        bad = []
        for t in result["towed"]:
            if abs(t["a_t_over_a_r"] - 1) > 0.10:
                bad.append(f"a_t / a_r = {t['a_t_over_a_r']:.3f} at U = {t['speed']} (10% allowed)")
            if abs(t["body_force"] - t["drag_balance"]) > 4 * t["body_force_err"] + 0.02 * t["drag_balance"]:
                bad.append(f"the body's force {t['body_force']:.4f} +- {t['body_force_err']:.4f} is not the balance "
                           f"{t['drag_balance']:.4f} at U = {t['speed']}")
        if bad:
            sys.exit("check failed: " + "; ".join(bad))
        print("check passed")
    if args.short:
        a_t = result["towed"][0]["a_t"]
        if abs(a_t / 2.00 - 1) > 0.15 or abs(a_r / 1.91 - 1) > 0.15:
            sys.exit(f"short check failed: a_t = {a_t:.3f}, a_r = {a_r:.3f}, expected within 15% of 2.00 and 1.91")
        print("short check passed")


if __name__ == "__main__":
    main()
