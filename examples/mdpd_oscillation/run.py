#!/usr/bin/python3
"""Free oscillation of a deformed drop of Warren's many-body DPD liquid: the l = 2 shape mode against
Rayleigh's frequency omega_0^2 = 8 sigma / (rho R^3) (seed 003, "Free oscillation of a droplet").

    PYTHONPATH=build/python /usr/bin/python3 examples/mdpd_oscillation/run.py
        [--sizes 3200 7000] [--seeds 4] [--stretch 0.12] [--relax 50] [--acf-steps 0] [--acf-state 0]
        [--equilibrate 2000] [--gap 1000] [--periods 1.6] [--every 10] [--threads 1]
        [--out out/mdpd_oscillation] [--states-from DIR] [--skip-stretch] [--analyse-only]

For each drop size N (particles):
 1. equilibrate: a ball of N simple-cubic lattice sites of density 6 (examples/mdpd_droplet/run.py's
    data file and box, 2 (R0 + 3.5)) runs `--equilibrate` steps with Maxwell velocities, then
    `--seeds` states are taken `--gap` steps apart (states.npz; the liquid density inside R0 - 2 and the
    particles of the drop are sampled every 50 steps from step 1,000 on, for the equimolar radius:
    equilibrium.json). `--states-from DIR` reuses DIR's states instead;
 2. for each state: the drop is stretched about its centre, volume-preservingly, x -> x (1 + e),
    y, z -> y, z / sqrt(1 + e) (e = `--stretch`), written as a LAMMPS data file with the particles'
    velocities, and run with `velocities = "file"` and another noise seed for `--periods` Rayleigh
    periods, recording the shape every `--every` steps. The affine stretch also strains the liquid's
    local structure, whose stress kicks the drop back within a few tenths of a time unit. With
    `--relax n` the stretched drop first runs n steps, then its straining flow (the symmetric part of
    the fitted velocity gradient) is removed and the run starts from that state: a release from rest;
 3. the shape signal Q(t) = G_xx - (G_yy + G_zz) / 2 (G the gyration tensor of the particles within
    R0 + 3 of the drop's centre) is fitted from t = 1 with Q0 exp(-beta t) cos(omega_d t + phi) + c, per
    run and for the mean over the states;
 4. with `--acf-steps n`: the unstretched drop (state `--acf-state`) runs n steps, and the autocorrelation of the
    traceless gyration tensor, C(t) = <T(0):T(t)> / <T:T> (all five l = 2 components; by Onsager's
    regression it decays like a small deformation released from rest; C(t) / C(0) is shown), is fitted the same way up to one
    Rayleigh period (every fluctuations_<k>.csv of the folder is used).

The frequencies are compared with Rayleigh's (slab sigma and the Laplace sigma), and the fitted
(beta, omega_d) with the least-damped mode of a viscous drop (viscous_mode) for the viscosity measured
by viscosity.toml. Writes under --out: N<count>/ (equilibrate/, stretch<k>/, fluctuations<k>/ run folders,
series_<k>.csv with t, Q, G_xx, G_yy, G_zz, fluctuations_<k>.csv), results.json, oscillation.png (Q(t) and
C(t) with the fits). check.py judges results.json.
"""
import argparse
import glob
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def _laplace_example():
    """examples/mdpd_droplet/run.py, for its lattice ball (write_drop) and box (geometry)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("mdpd_droplet_run", os.path.join(ROOT, "examples", "mdpd_droplet", "run.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_drop = _laplace_example()
geometry, write_drop = _drop.geometry, _drop.write_drop

SIGMA_SLAB, SIGMA_SLAB_ERR = 7.86, 0.10  # examples/mdpd_slab, docs/validation.md section 5
SIGMA_LAPLACE, SIGMA_LAPLACE_ERR = 6.81, 0.02  # Delta P R / 2 through the origin, examples/mdpd_droplet
ACF_PLOT_PERIODS = 1.3  # the autocorrelation is computed up to this many Rayleigh periods
ACF_FIT_PERIODS = 1.0  # the autocorrelation is fitted up to this many Rayleigh periods (beyond: noise)
ACF_BLOCKS = 5  # at most this many blocks of the fluctuation run, for the error bars of its fit
FIT_START = 1.0  # time units skipped before the fit: the stretched liquid's local structure relaxes


# Shear viscosity of the drops' liquid (viscosity.toml, reverse Poiseuille at rho = 6.12): eta = 5.47 +- 0.18.
NU, NU_ERR = 5.466 / 6.120, 0.179 / 6.120


def viscous_mode(sigma, rho, radius, nu, l=2):
    """The least-damped l-mode of a viscous drop in vacuum, s = -beta + i omega_d (time dependence e^(s t)),
    from the linearised Navier-Stokes equations with a free surface: inside the drop the velocity is a
    potential part grad(A r^l Y_lm) plus a vortical part curl curl(r psi(r) Y_lm) with psi = i_l(q r),
    q^2 = s / nu (i_l the modified spherical Bessel function); the pressure is -rho s A r^l Y_lm. Zero
    tangential stress and the normal-stress balance -p + 2 mu du_r/dr = -sigma (l - 1)(l + 2) zeta / R^2
    (zeta = u_r / s the surface displacement) at r = R give two linear equations in A and psi(R); s makes
    their determinant vanish (Chandrasekhar's characteristic equation for the viscous drop; derived here,
    not taken from a seed). Limits, checked: nu -> 0 gives Rayleigh's omega_0 and Lamb's
    beta = (l - 1)(2 l + 1) nu / R^2; the l = 2 mode stops oscillating at Oh = nu sqrt(rho / (sigma R)) = 0.77."""
    from scipy.optimize import fsolve
    from scipy.special import spherical_in

    mu, big_r = rho * nu, radius
    omega0 = math.sqrt(l * (l - 1) * (l + 2) * sigma / (rho * radius**3))

    def det(sv):
        q = np.sqrt(sv / nu)
        g = q * spherical_in(l, q * big_r, derivative=True) / spherical_in(l, q * big_r)  # psi'(R) / psi(R)
        t_a = 2 * (l - 1) * big_r ** (l - 2)
        t_psi = q * q + 2 * (l * l + l - 1) / big_r**2 - 2 * g / big_r
        curv = sigma * (l - 1) * (l + 2) / (big_r**2 * sv)
        n_a = rho * sv * big_r**l + 2 * mu * l * (l - 1) * big_r ** (l - 2) + curv * l * big_r ** (l - 1)
        n_psi = 2 * mu * l * (l + 1) * (g / big_r - 1 / big_r**2) + curv * l * (l + 1) / big_r
        d = (t_a * n_psi - t_psi * n_a) / (rho * omega0 * big_r**l)
        return [d.real, d.imag]

    beta_lamb = (l - 1) * (2 * l + 1) * nu / radius**2
    guess = [-beta_lamb / omega0, math.sqrt(max(1 - (beta_lamb / omega0) ** 2, 0.25))]
    root, _, ier, _ = fsolve(lambda v: det(complex(v[0], v[1]) * omega0), guess, full_output=True, xtol=1e-12)
    if ier != 1 or root[1] <= 0:
        return float("nan"), float("nan")
    return -root[0] * omega0, root[1] * omega0  # beta, omega_d


def sigma_nu_from_mode(beta, omega_d, rho, radius):
    """The surface tension and kinematic viscosity for which viscous_mode gives the measured beta, omega_d."""
    from scipy.optimize import fsolve

    def f(v):
        b, w = viscous_mode(v[0], rho, radius, v[1])
        return [b - beta, w - omega_d]

    sol, _, ier, _ = fsolve(f, [SIGMA_SLAB, NU], full_output=True)
    return (float(sol[0]), float(sol[1])) if ier == 1 else (float("nan"), float("nan"))


def minimum_image(d, box):
    return d - box * np.round(d / box)


class Shape:
    """Centre and gyration tensor of the particles within `rcut` of the drop's centre (the vapour is
    practically empty, so these are the drop's particles); the centre is followed from call to call."""

    def __init__(self, box, rcut, centre):
        self.box, self.rcut, self.centre = box, rcut, np.array(centre, dtype=float)

    def __call__(self, pos):
        for _ in range(3):
            d = minimum_image(pos - self.centre, self.box)
            inside = np.einsum("ij,ij->i", d, d) < self.rcut**2
            self.centre = (self.centre + d[inside].mean(axis=0)) % self.box
        d = minimum_image(pos - self.centre, self.box)
        d = d[np.einsum("ij,ij->i", d, d) < self.rcut**2]
        g = d.T @ d / len(d)
        return g, len(d), d


def positions(sim):
    p = sim.particles
    return np.column_stack([np.asarray(p.x), np.asarray(p.y), np.asarray(p.z)])


def write_stretched(path, state, box, centre, e):
    """A state (columns x, y, z, vx, vy, vz in id order, ids 1..n) stretched about `centre` by
    (1 + e, 1/sqrt(1 + e), 1/sqrt(1 + e)) (determinant 1), wrapped into the box, with its velocities."""
    pos = state[:, :3]
    d = minimum_image(pos - centre, box)
    s = np.array([1 + e, 1 / math.sqrt(1 + e), 1 / math.sqrt(1 + e)])
    pos = (centre + d * s) % box
    pos[pos >= box] -= box  # a rounding of x % box up to box itself
    n = len(pos)
    with open(path, "w") as f:
        f.write(f"Warren drop stretched by e = {e} (examples/mdpd_oscillation/run.py)\n\n")
        f.write(f"{n} atoms\n1 atom types\n\n0 {box} xlo xhi\n0 {box} ylo yhi\n0 {box} zlo zhi\n\n")
        f.write("Masses\n\n1 1.0\n\nAtoms # atomic\n\n")
        for k in range(n):
            f.write(f"{k + 1} 1 {pos[k, 0]:.10f} {pos[k, 1]:.10f} {pos[k, 2]:.10f}\n")
        f.write("\nVelocities\n\n")
        for k in range(n):
            f.write(f"{k + 1} {state[k, 3]:.12g} {state[k, 4]:.12g} {state[k, 5]:.12g}\n")


def make_spec(mesodpd, n, box, data, velocities, seed, steps, thermo_every):
    spec = mesodpd.Spec.from_toml(os.path.join(HERE, "oscillation.toml"))
    spec["system"]["box"] = [box, box, box]
    spec["system"]["seed"] = seed
    spec["init"] = {"lammps_data": os.path.abspath(data), "velocities": velocities}
    spec["run"]["steps"] = steps
    spec["output"]["thermo_every"] = thermo_every
    return spec


def damped_cosine(t, q0, beta, omega, phi, c):
    return q0 * np.exp(-beta * t) * np.cos(omega * t + phi) + c


def fit(t, q, omega_guess, beta_guess, t_max=float("inf")):
    """Least-squares fit of the damped cosine for FIT_START <= t <= t_max; returns the parameters and their
    standard errors (from the covariance, the residual scatter as the noise)."""
    from scipy.optimize import curve_fit

    m = (t >= FIT_START) & (t <= t_max)
    p0 = [q[m][0] if q[m][0] != 0 else 1.0, beta_guess, omega_guess, 0.0, 0.0]
    popt, pcov = curve_fit(damped_cosine, t[m], q[m], p0=p0, maxfev=20000)
    if popt[0] < 0:  # the same curve with a positive amplitude
        popt[0], popt[3] = -popt[0], popt[3] + math.pi
    popt[3] = (popt[3] + math.pi) % (2 * math.pi) - math.pi
    resid = q[m] - damped_cosine(t[m], *popt)
    return {"q0": popt[0], "beta": popt[1], "omega_d": abs(popt[2]), "phi": popt[3], "c": popt[4],
            "q0_err": math.sqrt(pcov[0, 0]), "beta_err": math.sqrt(pcov[1, 1]),
            "omega_d_err": math.sqrt(pcov[2, 2]), "rms_residual": float(np.sqrt(np.mean(resid**2))),
            "omega_0": math.sqrt(popt[2] ** 2 + popt[1] ** 2)}


def equilibrate(mesodpd, n, args, root):
    """Equilibrate the lattice ball of n particles; keep `seeds` states `gap` steps apart (states.npz) and
    the liquid density, drop size and thermal shape scatter (equilibrium.json)."""
    r0, box, _, _ = geometry(n)
    eq_dir = os.path.join(root, "equilibrate")
    os.makedirs(eq_dir, exist_ok=True)
    write_drop(os.path.join(eq_dir, "drop.data"), n, box, 2003 + n)
    last = args.equilibrate + (args.seeds - 1) * args.gap
    spec = make_spec(mesodpd, n, box, os.path.join(eq_dir, "drop.data"), "maxwell", 3003 + n, last, 100)
    sim = mesodpd.Simulation(spec, out=os.path.join(eq_dir, "out"), threads=args.threads)
    shape = Shape(box, r0 + 3.0, [box / 2] * 3)
    rho_in, n_drop, q_eq, states = [], [], [], {}
    r_core = r0 - 2.0

    def sample(s):
        g, count, d = shape(positions(s))
        if s.current_step >= 1000:
            rho_in.append(np.count_nonzero(np.einsum("ij,ij->i", d, d) < r_core**2) / (4 / 3 * math.pi * r_core**3))
            n_drop.append(count)
            q_eq.append(g[0, 0] - 0.5 * (g[1, 1] + g[2, 2]))
        if s.current_step >= args.equilibrate and (s.current_step - args.equilibrate) % args.gap == 0:
            k = len(states) // 2
            snap = s.snapshot()
            states[f"state{k}"] = np.column_stack([snap[c] for c in ("x", "y", "z", "vx", "vy", "vz")])
            states[f"centre{k}"] = shape.centre.copy()

    sim.add_callback(sample, every=50)
    print(f"N = {n}: equilibrating {last} steps in a {box}^3 box", flush=True)
    sim.run()
    np.savez(os.path.join(root, "states.npz"), **states)
    rho = float(np.mean(rho_in))
    blocks = np.array_split(np.array(rho_in), 10)
    eq = {"particles": n, "box": box, "r0": r0, "rho_in": rho,
          "rho_in_err": float(np.std([b.mean() for b in blocks], ddof=1) / math.sqrt(len(blocks))),
          "drop_particles": float(np.mean(n_drop)),
          "radius": (3 * float(np.mean(n_drop)) / (4 * math.pi * rho)) ** (1 / 3),
          "q_equilibrium_rms": float(np.sqrt(np.mean(np.square(q_eq)))), "states": len(states) // 2,
          "equilibrate": args.equilibrate, "gap": args.gap}
    with open(os.path.join(root, "equilibrium.json"), "w") as f:
        json.dump(eq, f, indent=2)


def release_from_rest(mesodpd, n, box, rcut, centre, data, seed, relax):
    """Run the stretched drop `relax` steps (its affinely strained local structure relaxes; its stress pushes
    the drop back), then remove the drop's straining flow: the symmetric part S of the velocity gradient
    fitted to the particles within rcut of the centre (v = v_cm + L d by least squares), so that the shape
    mode starts from rest. Writes released.data next to `data`; returns its path and the removed S_xx."""
    spec = make_spec(mesodpd, n, box, data, "file", seed, relax, relax)
    sim = mesodpd.Simulation(spec, threads=None)
    sim.run()
    snap = sim.snapshot()
    state = np.column_stack([snap[c] for c in ("x", "y", "z", "vx", "vy", "vz")])
    shape = Shape(box, rcut, centre)
    shape(state[:, :3])
    d = minimum_image(state[:, :3] - shape.centre, box)
    inside = np.einsum("ij,ij->i", d, d) < rcut**2
    x = np.hstack([np.ones((np.count_nonzero(inside), 1)), d[inside]])
    coef = np.linalg.lstsq(x, state[inside, 3:], rcond=None)[0]
    grad = coef[1:].T  # L[a, b] = d v_a / d x_b
    strain = 0.5 * (grad + grad.T)
    state[inside, 3:] -= d[inside] @ strain.T
    path = os.path.join(os.path.dirname(data), "released.data")
    write_stretched(path, state, box, shape.centre, 0.0)
    return path, float(strain[0, 0])


def oscillate(mesodpd, n, args, root):
    """Stretch each saved state and run it, recording the shape (series_<k>.csv)."""
    r0, box, _, _ = geometry(n)
    with open(os.path.join(root, "equilibrium.json")) as f:
        eq = json.load(f)
    states = np.load(os.path.join(root, "states.npz"))
    dt = 0.01
    omega_r = math.sqrt(8 * SIGMA_SLAB / (eq["rho_in"] * eq["radius"] ** 3))
    steps = int(round(args.periods * 2 * math.pi / omega_r / dt / 100)) * 100
    rates = []
    for k in range(eq["states"]):
        run_dir = os.path.join(root, f"stretch{k}")
        os.makedirs(run_dir, exist_ok=True)
        data = os.path.join(run_dir, "stretched.data")
        centre = states[f"centre{k}"]
        write_stretched(data, states[f"state{k}"], box, centre, args.stretch)
        if args.relax > 0:
            data, rate = release_from_rest(mesodpd, n, box, r0 + 3.0, centre, data, 6003 + 10 * n + k, args.relax)
            rates.append(rate)
        spec = make_spec(mesodpd, n, box, data, "file", 4003 + 10 * n + k, steps, 100)
        sim = mesodpd.Simulation(spec, out=os.path.join(run_dir, "out"), threads=args.threads)
        shape = Shape(box, r0 + 3.0, centre)
        rows = []

        def record(s):
            g, _, _ = shape(positions(s))
            rows.append((s.current_step * dt, g[0, 0] - 0.5 * (g[1, 1] + g[2, 2]), g[0, 0], g[1, 1], g[2, 2]))

        record(sim)
        sim.add_callback(record, every=args.every)
        print(f"N = {n}: stretched state {k} ({k + 1}/{eq['states']}), e = {args.stretch}, {steps} steps", flush=True)
        sim.run()
        np.savetxt(os.path.join(root, f"series_{k}.csv"), np.array(rows), delimiter=",",
                   header="t,Q,G_xx,G_yy,G_zz", comments="")
    with open(os.path.join(root, "oscillation.json"), "w") as f:
        json.dump({"stretch": args.stretch, "steps": steps, "every": args.every, "relax": args.relax,
                   "removed_strain_rate_xx": rates}, f, indent=2)


def fluctuate(mesodpd, n, args, root):
    """The unstretched drop (state `--acf-state` k, its velocities, another noise seed) for `--acf-steps`
    steps: the gyration tensor every `--every` steps (fluctuations_<k>.csv), for the autocorrelation of
    its thermal l = 2 shape fluctuations."""
    r0, box, _, _ = geometry(n)
    k = args.acf_state
    states = np.load(os.path.join(root, "states.npz"))
    run_dir = os.path.join(root, f"fluctuations{k}")
    os.makedirs(run_dir, exist_ok=True)
    data = os.path.join(run_dir, "state.data")
    write_stretched(data, states[f"state{k}"], box, states[f"centre{k}"], 0.0)
    spec = make_spec(mesodpd, n, box, data, "file", 5003 + n + 1000 * k, args.acf_steps, 1000)
    sim = mesodpd.Simulation(spec, out=os.path.join(run_dir, "out"), threads=args.threads)
    shape = Shape(box, r0 + 3.0, states[f"centre{k}"])
    rows = []

    def record(s):
        g, _, _ = shape(positions(s))
        rows.append((s.current_step * 0.01, g[0, 0], g[1, 1], g[2, 2], g[0, 1], g[0, 2], g[1, 2]))

    sim.add_callback(record, every=args.every)
    print(f"N = {n}: unstretched drop (state {k}), {args.acf_steps} steps for the shape fluctuations", flush=True)
    sim.run()
    np.savetxt(os.path.join(root, f"fluctuations_{k}.csv"), np.array(rows), delimiter=",",
               header="t,G_xx,G_yy,G_zz,G_xy,G_xz,G_yz", comments="")


def shape_acf(g, lags):
    """Unnormalised C(t) = <T(0) : T(t)>, T the traceless part of the gyration tensor (rotation invariant:
    the five l = 2 components together); g: rows G_xx, G_yy, G_zz, G_xy, G_xz, G_yz. The mean of T is
    zero for a spherical drop, so it is not subtracted (subtracting a short block's mean would bias C)."""
    tr = g[:, :3].sum(axis=1, keepdims=True) / 3
    t = np.hstack([g[:, :3] - tr, g[:, 3:]])
    w = np.array([1, 1, 1, 2, 2, 2.0])  # off-diagonal components count twice in T : T
    return np.array([np.mean(np.sum(w * t[: len(t) - k] * t[k:], axis=1)) for k in lags])


def first_zero(t, q):
    """The first time the signal, positive at t = 0, reaches zero (linear interpolation); NaN if never."""
    below = np.nonzero(q <= 0)[0]
    if len(below) == 0 or below[0] == 0:
        return float("nan")
    j = below[0]
    return float(t[j - 1] + q[j - 1] / (q[j - 1] - q[j]) * (t[j] - t[j - 1]))


def zero_from_rest(beta, omega_d):
    """First zero of exp(-beta t) (cos(omega_d t) + (beta / omega_d) sin(omega_d t)): a damped oscillator
    released from rest."""
    return (math.pi - math.atan2(omega_d, beta)) / omega_d


def analyse_size(n, out):
    root = os.path.join(out, f"N{n}")
    with open(os.path.join(root, "equilibrium.json")) as f:
        eq = json.load(f)
    with open(os.path.join(root, "oscillation.json")) as f:
        eq.update(json.load(f))
    rho, radius = eq["rho_in"], eq["radius"]
    omega = {name: math.sqrt(8 * s / (rho * radius**3)) for name, s in
             [("slab", SIGMA_SLAB), ("laplace", SIGMA_LAPLACE)]}
    series = [np.loadtxt(os.path.join(root, f"series_{k}.csv"), delimiter=",", skiprows=1) for k in range(eq["states"])]
    fits = [fit(s[:, 0], s[:, 1], omega["slab"], 0.1) for s in series]
    t = series[0][:, 0]
    q_mean = np.mean([s[:, 1] for s in series], axis=0)
    mean_fit = fit(t, q_mean, omega["slab"], 0.1)
    # Sign changes of the mean signal (after the fit start): the shape passes through the sphere.
    m = t >= FIT_START
    crossings = int(np.count_nonzero(np.diff(np.sign(q_mean[m] - mean_fit["c"])) != 0))
    first_min = int(np.argmin(q_mean))
    od = np.array([f["omega_d"] for f in fits])
    o0 = np.array([f["omega_0"] for f in fits])
    be = np.array([f["beta"] for f in fits])
    spread = (lambda a: float(np.std(a, ddof=1) / math.sqrt(len(a))) if len(a) > 1 else float("nan"))
    acf = None
    period = 2 * math.pi / omega["slab"]
    paths = sorted(glob.glob(os.path.join(root, "fluctuations_*.csv")))
    if paths:
        runs = [np.loadtxt(p, delimiter=",", skiprows=1) for p in paths]
        dt_s = runs[0][1, 0] - runs[0][0, 0]
        lags = np.arange(int(round(ACF_PLOT_PERIODS * period / dt_s)))
        tau = lags * dt_s
        # Blocks of at least twice the longest lag, from every fluctuation run; C(t) is their mean.
        blocks = [b for g in runs for b in np.array_split(g, max(1, min(ACF_BLOCKS, len(g) // (2 * len(lags)))))]
        raw = [shape_acf(b[:, 1:], lags) for b in blocks]
        c = np.mean(raw, axis=0) / np.mean(raw, axis=0)[0]
        cs = [r / r[0] for r in raw]
        block_fits = [fit(tau, cb, omega["slab"], 0.1, ACF_FIT_PERIODS * period) for cb in cs]
        acf = {"t": tau.tolist(), "c": c.tolist(), "fit": fit(tau, c, omega["slab"], 0.1, ACF_FIT_PERIODS * period),
               "t_zero": first_zero(tau, c), "t_zero_blocks": [first_zero(tau, cb) for cb in cs],
               "duration": float(sum(g[-1, 0] - g[0, 0] for g in runs)), "runs": len(runs), "blocks": len(blocks),
               "omega_d_blocks": [b["omega_d"] for b in block_fits], "beta_blocks": [b["beta"] for b in block_fits],
               "omega_0_blocks": [b["omega_0"] for b in block_fits]}
        for key in ("omega_d", "beta", "omega_0", "t_zero"):  # no error bar from fewer than three blocks
            v = np.array(acf[f"{key}_blocks"])
            acf[f"{key}_sem"] = float(np.std(v, ddof=1) / math.sqrt(len(v))) if len(v) >= 3 else float("nan")
    res = dict(eq)
    res.update({"fluctuations": acf,
        "omega_rayleigh_slab": omega["slab"], "omega_rayleigh_laplace": omega["laplace"],
        "period_rayleigh_slab": 2 * math.pi / omega["slab"],
        "fits": fits, "mean_fit": mean_fit, "sign_changes": crossings,
        "q_mean_start": float(q_mean[0]), "q_mean_min": float(q_mean[first_min]), "t_min": float(t[first_min]),
        "t_zero": first_zero(t, q_mean - mean_fit["c"]),
        "omega_d_mean": float(od.mean()), "omega_d_sem": spread(od),
        "omega_0_mean": float(o0.mean()), "omega_0_sem": spread(o0),
        "beta_mean": float(be.mean()), "beta_sem": spread(be),
        "omega_0_over_rayleigh_slab": float(o0.mean()) / omega["slab"],
        "omega_d_over_rayleigh_slab": float(od.mean()) / omega["slab"],
        "omega_0_over_rayleigh_laplace": float(o0.mean()) / omega["laplace"],
        # Lamb: beta = (l - 1)(2 l + 1) nu / R^2 = 5 nu / R^2 for l = 2: the viscosity the damping implies.
        "nu_from_lamb": float(be.mean()) * radius**2 / 5, "beta_lamb": 5 * NU / radius**2,
        "nu_poiseuille": NU, "nu_poiseuille_err": NU_ERR,
        "ohnesorge_slab": NU * math.sqrt(rho / (SIGMA_SLAB * radius)),
    })
    # The viscous drop's mode for the slab's (and the Laplace) sigma with the Poiseuille viscosity, and the
    # sigma and nu that reproduce the fitted mode (mean curve; fluctuation autocorrelation).
    for name, sig in [("slab", SIGMA_SLAB), ("laplace", SIGMA_LAPLACE)]:
        b, w = viscous_mode(sig, rho, radius, NU)
        res[f"viscous_theory_{name}"] = {"beta": b, "omega_d": w, "t_zero_from_rest": zero_from_rest(b, w)}
    for key, f in [("mean_fit", mean_fit), ("fluctuations", acf["fit"] if acf else None)]:
        if f is not None:
            sig, nu = sigma_nu_from_mode(f["beta"], f["omega_d"], rho, radius)
            res[f"sigma_nu_from_{key}"] = {"sigma": sig, "nu": nu}
    return res, t, series, q_mean


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[3200, 7000], help="particles per drop")
    ap.add_argument("--seeds", type=int, default=4, help="stretched states (and noise seeds) per drop")
    ap.add_argument("--stretch", type=float, default=0.12)
    ap.add_argument("--equilibrate", type=int, default=2000)
    ap.add_argument("--gap", type=int, default=1000, help="steps between the equilibrated states")
    ap.add_argument("--periods", type=float, default=1.6, help="run length in Rayleigh periods (slab sigma)")
    ap.add_argument("--every", type=int, default=10, help="steps between shape samples")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "mdpd_oscillation"))
    ap.add_argument("--acf-steps", type=int, default=0,
                    help="also run the unstretched drop this long for the autocorrelation of its shape")
    ap.add_argument("--acf-state", type=int, default=0, help="the equilibrated state the fluctuation run starts from")
    ap.add_argument("--skip-stretch", action="store_true", help="with --states-from: only the fluctuation run")
    ap.add_argument("--relax", type=int, default=50,
                    help="steps after the stretch before the drop's straining flow is removed (0: none, the drop is kicked)")
    ap.add_argument("--analyse-only", action="store_true")
    ap.add_argument("--states-from", default=None,
                    help="an earlier --out: stretch its equilibrated states instead of equilibrating again")
    args = ap.parse_args()
    if not args.analyse_only:
        import mesodpd

        for n in args.sizes:
            root = os.path.join(args.out, f"N{n}")
            os.makedirs(root, exist_ok=True)
            if args.states_from:  # the states (and equilibrium.json) of an earlier run, stretched anew
                import shutil

                for name in ("states.npz", "equilibrium.json"):
                    if os.path.abspath(args.states_from) != os.path.abspath(args.out):
                        shutil.copy(os.path.join(args.states_from, f"N{n}", name), os.path.join(root, name))
            else:
                equilibrate(mesodpd, n, args, root)
            if not args.skip_stretch:
                oscillate(mesodpd, n, args, root)
            if args.acf_steps > 0:
                fluctuate(mesodpd, n, args, root)
    results = []
    curves = []
    for n in args.sizes:
        res, t, series, q_mean = analyse_size(n, args.out)
        results.append(res)
        curves.append((res, t, series, q_mean))
    summary = {"sigma_slab": SIGMA_SLAB, "sigma_slab_err": SIGMA_SLAB_ERR, "sigma_laplace": SIGMA_LAPLACE,
               "fit_start": FIT_START, "drops": results}
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(f"{'N':>6} {'R':>6} {'rho':>6} {'w_R(slab)':>9} {'w_R(Lapl)':>9} {'w_d':>14} {'beta':>14} {'w_0':>14} "
          f"{'w_0/w_R':>7} {'w_d/w_R':>7} {'nu_Lamb':>7}")
    for r in results:
        print(f"{r['particles']:6d} {r['radius']:6.3f} {r['rho_in']:6.3f} {r['omega_rayleigh_slab']:9.4f} "
              f"{r['omega_rayleigh_laplace']:9.4f} {r['omega_d_mean']:7.4f}+-{r['omega_d_sem']:.4f} "
              f"{r['beta_mean']:7.4f}+-{r['beta_sem']:.4f} {r['omega_0_mean']:7.4f}+-{r['omega_0_sem']:.4f} "
              f"{r['omega_0_over_rayleigh_slab']:7.3f} {r['omega_d_over_rayleigh_slab']:7.3f} {r['nu_from_lamb']:7.3f}")
        mf = r["mean_fit"]
        print(f"       mean curve: w_d = {mf['omega_d']:.4f} +- {mf['omega_d_err']:.4f}, beta = {mf['beta']:.4f} +- "
              f"{mf['beta_err']:.4f}, w_0 = {mf['omega_0']:.4f}, Q0 = {mf['q0']:.3f}, sign changes {r['sign_changes']}, "
              f"equilibrium rms Q = {r['q_equilibrium_rms']:.3f}")
        for name in ("slab", "laplace"):
            v = r[f"viscous_theory_{name}"]
            print(f"       viscous theory ({name} sigma, nu = {NU:.3f}): w_d = {v['omega_d']:.4f}, beta = {v['beta']:.4f}, "
                  f"first zero from rest at t = {v['t_zero_from_rest']:.2f}")
        print(f"       first zero of the mean Q at t = {r['t_zero']:.2f}, minimum {r['q_mean_min']:.3f} at t = {r['t_min']:.1f}")
        if r["fluctuations"]:
            a = r["fluctuations"]
            af = a["fit"]
            print(f"       fluctuations ({a['duration']:.0f} time units): w_d = {af['omega_d']:.4f} +- {a['omega_d_sem']:.4f}, "
                  f"beta = {af['beta']:.4f} +- {a['beta_sem']:.4f}, w_0 = {af['omega_0']:.4f} +- {a['omega_0_sem']:.4f}, "
                  f"first zero at t = {a['t_zero']:.2f} +- {a['t_zero_sem']:.2f} ({a['blocks']} blocks)")
        for key in ("mean_fit", "fluctuations"):
            if f"sigma_nu_from_{key}" in r:
                v = r[f"sigma_nu_from_{key}"]
                print(f"       sigma, nu reproducing the {key} mode: {v['sigma']:.3f}, {v['nu']:.3f}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(len(curves), 2, figsize=(11, 3.4 * len(curves)), squeeze=False)
        for (ax, ax2), (r, t, series, q_mean) in zip(axes, curves):
            for s in series:
                ax.plot(s[:, 0], s[:, 1], lw=0.6, alpha=0.5, color="grey")
            ax.plot(t, q_mean, lw=1.2, color="C0", label=f"mean of {len(series)} runs")
            mf = r["mean_fit"]
            tf = t[t >= FIT_START]
            ax.plot(tf, damped_cosine(tf, mf["q0"], mf["beta"], mf["omega_d"], mf["phi"], mf["c"]), "--", color="C3",
                    label=f"fit: $\\omega_d$ = {mf['omega_d']:.3f}, $\\beta$ = {mf['beta']:.3f}, "
                          f"$\\omega_0$ = {mf['omega_0']:.3f}")
            wr = r["omega_rayleigh_slab"]
            how = "released from rest" if r.get("relax") else "kicked"
            ax.set_title(f"drop stretched by e = {r['stretch']}, {how}: N = {r['particles']}, R = {r['radius']:.2f}, "
                         f"Rayleigh $\\omega_0$ = {wr:.3f} (slab $\\sigma$)", fontsize=9)
            ax.axhline(0, color="k", lw=0.5)
            ax.set_xlabel("t")
            ax.set_ylabel("Q = G_xx - (G_yy + G_zz)/2")
            ax.legend(fontsize=8)
            acf = r["fluctuations"]
            if acf is None:
                ax2.set_axis_off()
                continue
            tau, c, af = np.array(acf["t"]), np.array(acf["c"]), acf["fit"]
            ax2.plot(tau, c, color="C0", label=f"unstretched drop, {acf['duration']:.0f} time units")
            tf = tau[tau >= FIT_START]
            ax2.plot(tf, damped_cosine(tf, af["q0"], af["beta"], af["omega_d"], af["phi"], af["c"]), "--", color="C3",
                     label=f"fit: $\\omega_d$ = {af['omega_d']:.3f}, $\\beta$ = {af['beta']:.3f}, "
                           f"$\\omega_0$ = {af['omega_0']:.3f}")
            ax2.axhline(0, color="k", lw=0.5)
            ax2.set_title("thermal shape fluctuations: C(t) = <T(0):T(t)> / <T:T>", fontsize=9)
            ax2.set_xlabel("t")
            ax2.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "oscillation.png"), dpi=120)
    except ImportError:
        print("matplotlib missing: no plot")
    return 0


if __name__ == "__main__":
    sys.exit(main())
