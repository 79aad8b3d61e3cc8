#!/usr/bin/python3
"""Continuum reference for the confined single pillar of seed 004 Sect. 4.1.

Steady incompressible 2-D flow in the DPD example's geometry: periodic along x with period
l = 60, no-slip plates at z = 0 and z = h = 30, a fixed circular cylinder of diameter d = 6
centred at (30, 15), the fluid driven by a uniform body force g along x. Lengths scale with d,
so the problem depends on the Reynolds number only (h = 5 d, l = 10 d).

Method: a standard D2Q9 lattice Boltzmann scheme with the two-relaxation-time (TRT) collision,
the "magic" parameter Lambda = 3/16, the incompressible form of the equilibrium (rho0 = 1) and
Guo's forcing split into its even and odd parts, so that the steady state is that of the body
force exactly. Plates: half-way bounce-back (with TRT and Lambda = 3/16 the plane Poiseuille
profile is reproduced exactly, see --check). Cylinder: linearly interpolated bounce-back
(Bouzidi-Firdaouss-Lallemand), wall distances q from the exact circle. Forces on the cylinder and
on the plates by momentum exchange on the boundary links; in steady state their sum equals the
total body force on the fluid (checked). Because the cylinder is centred between the plates the
steady flow is mirror-symmetric about z = h/2; by default only the lower half is computed, with a
specular (mirror) boundary at the mid-plane (`--full` computes the whole channel; the README lists
the check that both agree).

The body force is found for a target mean velocity: during a controlled phase g is adjusted every
step from the measured momentum loss to the walls (so the slow flux mode does not set the
convergence time); then g is frozen and a check block verifies that the mean velocity is steady
(relative change below 1e-5).

Outputs (per Reynolds number and resolution N = nodes per diameter):
  re     = U d / nu, U the mean x velocity over the fluid area (channel minus cylinder)
  cd     = 2 F_D / (U^2 d) per unit length and density (seed 004 Eq. 10), F_D by momentum exchange
  cd_balance = the same with F_D = total body force - plate force (steady-state balance)
  f_cylinder_fraction = F_D / total body force on the fluid
  g_star = g d^3 / nu^2 (dimensionless body force) and u_over_poiseuille = U / (g h^2 / (12 nu)),
  so that a DPD run with body force g and kinematic viscosity nu can be placed on the curve.

The mirror-symmetric steady state stops being the flow that is realised once it is unstable
(vortex shedding): --stability follows a small antisymmetric disturbance in the whole channel and
reports its growth rate; --shedding averages the drag of the shedding flow.

Run:  /usr/bin/python3 examples/pillar/lbm_reference.py            (both resolutions, writes CSVs)
      /usr/bin/python3 examples/pillar/lbm_reference.py --check    (empty-channel Poiseuille test)
      --res 12 --re 10 20 --full   etc., see --help; examples/pillar/README.md has the numbers.
"""
import argparse
import csv
import math
import os
import sys
import time

import numpy as np

# D2Q9 with directions 1-4 and their opposites 5-8 stored in two contiguous blocks.
CX = np.array([0, 1, 0, 1, -1, -1, 0, -1, 1])
CZ = np.array([0, 0, 1, 1, 1, 0, -1, -1, -1])
W = np.array([4 / 9, 1 / 9, 1 / 9, 1 / 36, 1 / 36, 1 / 9, 1 / 9, 1 / 36, 1 / 36])
OPP = np.array([0, 5, 6, 7, 8, 1, 2, 3, 4])
# MIRZ[k]: the direction mirrored about a plane z = const
MIRZ = np.array([[m for m in range(9) if CX[m] == CX[k] and CZ[m] == -CZ[k]][0] for k in range(9)])
LAMBDA = 3.0 / 16.0

HERE = os.path.dirname(os.path.abspath(__file__))


class Channel:
    """Lattice, geometry and boundary links for one resolution N (nodes per diameter)."""

    def __init__(self, n_d, cylinder=True, symmetric=True, nx=None, diameter_scale=1.0):
        if n_d % 2 or n_d < 4:
            raise SystemExit("lbm_reference: the resolution (nodes per diameter) must be even and at least 4, "
                             "got %d" % n_d)
        self.n_d = n_d
        self.nx = 10 * n_d if nx is None else nx
        self.nz_full = 5 * n_d                     # h = 5 d
        self.symmetric = symmetric
        self.nz = self.nz_full // 2 if symmetric else self.nz_full
        nx, nz = self.nx, self.nz
        # diameter_scale != 1 changes the cylinder only (d/h = 0.2 diameter_scale), for sensitivity runs
        self.xc, self.zc, self.radius = 5.0 * n_d, 2.5 * n_d, 0.5 * n_d * diameter_scale
        self.cylinder = cylinder
        i, j = np.meshgrid(np.arange(nx), np.arange(nz), indexing="ij")
        self.solid = self._inside(i + 0.5, j + 0.5) if cylinder else np.zeros((nx, nz), bool)
        self.fluid = ~self.solid
        self.n_fluid = int(self.fluid.sum())
        self.fluid_flat = self.fluid.ravel().astype(float)
        # Pull streaming: f_new[k](x) = f_post[k](x - c_k), periodic in both axes here; the
        # populations wrapped across z (and those coming out of the cylinder) are overwritten.
        idx = np.arange(nx * nz).reshape(nx, nz)
        self.src = np.concatenate([np.roll(idx, (CX[k], CZ[k]), axis=(0, 1)).ravel() + k * nx * nz
                                   for k in range(9)])
        self._links()

    def _inside(self, x, z):
        return (x - self.xc) ** 2 + (z - self.zc) ** 2 < self.radius ** 2

    def _q(self, x, z, k):
        """Fraction q of the link from (x, z) along c_k at which it crosses the circle."""
        px, pz = x - self.xc, z - self.zc
        a = CX[k] ** 2 + CZ[k] ** 2
        b = px * CX[k] + pz * CZ[k]
        c = px * px + pz * pz - self.radius ** 2
        t = (-b - math.sqrt(b * b - a * c)) / a
        if not 0.0 < t <= 1.0:
            raise RuntimeError("wall distance out of range: %g" % t)
        return t

    def _flat(self, k, i, j):
        """Flat index of population k at node (i, j) given in full-channel coordinates;
        nodes above the mid-plane are mapped to their mirror image (symmetric mode)."""
        i %= self.nx
        if self.symmetric and j >= self.nz:
            j = 2 * self.nz - 1 - j
            k = MIRZ[k]
        return (k * self.nx + i) * self.nz + j

    def _links(self):
        """Boundary links (fluid node x, direction k pointing out of the fluid). After streaming the
        population OPP[k] at x is unknown and is set to a * f_post[s1] + b * f_post[s2]."""
        nx, nz = self.nx, self.nz
        dst, s1, s2, a, b, kind, cxk, czk = [], [], [], [], [], [], [], []
        for i in range(nx):
            for j in range(nz):
                if self.solid[i, j]:
                    continue
                x, z = i + 0.5, j + 0.5
                for k in range(1, 9):
                    ni, nj = i + CX[k], j + CZ[k]
                    d = self._flat(OPP[k], i, j)
                    here = self._flat(k, i, j)
                    if nj < 0 or (not self.symmetric and nj >= nz):       # plate: half-way bounce-back
                        dst.append(d); s1.append(here); s2.append(here); a.append(1.0); b.append(0.0)
                        kind.append(1); cxk.append(CX[k])
                    elif self.cylinder and self._inside(x + CX[k], z + CZ[k]):
                        q = self._q(x, z, k)
                        back_i, back_j = i - CX[k], j - CZ[k]
                        back_ok = (0 <= back_j) and not self._inside(back_i + 0.5, back_j + 0.5)
                        if q < 0.5 and back_ok:
                            dst.append(d); s1.append(here); s2.append(self._flat(k, back_i, back_j))
                            a.append(2 * q); b.append(1 - 2 * q)
                        elif q >= 0.5:
                            dst.append(d); s1.append(here); s2.append(self._flat(OPP[k], i, j))
                            a.append(0.5 / q); b.append((2 * q - 1) / (2 * q))
                        else:                                       # no second fluid node: plain bounce-back
                            dst.append(d); s1.append(here); s2.append(here); a.append(1.0); b.append(0.0)
                        kind.append(2); cxk.append(CX[k]); czk.append(CZ[k])
                    elif self.symmetric and nj >= nz:               # mirror plane: specular reflection
                        # in the full channel OPP[k] streams in from (i + cx_k, nz), the mirror
                        # image of (i + cx_k, nz - 1): _flat maps it and mirrors the direction
                        dst.append(d)
                        s = self._flat(OPP[k], ni, nj)
                        s1.append(s); s2.append(s); a.append(1.0); b.append(0.0)
                        kind.append(0); cxk.append(CX[k])
        self.dst, self.s1, self.s2 = np.array(dst), np.array(s1), np.array(s2)
        n = nx * nz
        self.out = OPP[self.dst // n] * n + self.dst % n      # outgoing population k at the node
        self.a, self.b = np.array(a), np.array(b)
        self.kind, self.cxk = np.array(kind), np.array(cxk, float)
        self.czk_cyl = np.array(czk, float)              # z components of the cylinder links
        self.plate = self.kind == 1
        self.cyl = self.kind == 2
        self.n_cyl_links = int(self.cyl.sum())


class Solver:
    def __init__(self, ch, nu, g=0.0):
        self.ch = ch
        self.set_nu(nu)
        self.g = g
        self.f = np.empty((9, ch.nx, ch.nz))
        self.track_lift = False
        self.lift = 0.0

    def set_nu(self, nu):
        self.nu = nu
        tau_p = 3.0 * nu + 0.5
        self.wp = 1.0 / tau_p
        self.wm = 1.0 / (LAMBDA / (tau_p - 0.5) + 0.5)

    def init_poiseuille(self, u_mean):
        ch = self.ch
        z = (np.arange(ch.nz) + 0.5) / ch.nz_full
        ux = np.broadcast_to(6.0 * u_mean * z * (1 - z), (ch.nx, ch.nz)).copy()
        ux[ch.solid] = 0.0
        self.set_equilibrium(np.ones_like(ux), ux, np.zeros_like(ux))

    def set_equilibrium(self, rho, ux, uz):
        for k in range(9):
            cu = CX[k] * ux + CZ[k] * uz
            self.f[k] = W[k] * (rho + 3 * cu + 4.5 * cu * cu - 1.5 * (ux * ux + uz * uz))

    def macros(self):
        f = self.f
        rho = f.sum(0)
        ux = np.tensordot(CX, f, 1) + 0.5 * self.g
        uz = np.tensordot(CZ, f, 1)
        return rho, ux, uz

    def step(self):
        """One collide-stream-boundary step. Returns (U, F_plates, F_cylinder) with U the mean x
        velocity over the fluid before the step and the forces the x momentum given to the
        boundaries during it (lattice units, per unit length)."""
        ch, f, g = self.ch, self.f, self.g
        wp, wm = self.wp, self.wm
        fa, fb = f[1:5], f[5:9]
        fp = fa + fb
        fm = fa - fb
        rho = f[0] + fp.sum(0)
        ux = fm[0] + fm[2] - fm[3] + 0.5 * g
        uz = fm[1] + fm[2] + fm[3]
        usq = ux * ux + uz * uz
        cu = np.empty_like(fp)
        cu[0] = ux
        cu[1] = uz
        np.add(ux, uz, out=cu[2])
        np.subtract(uz, ux, out=cu[3])
        w4 = W[1:5, None, None]
        cx4 = CX[1:5, None, None]
        # even part (sum over the pair): relaxes with wp; odd part (difference): with wm
        eqp = 2 * w4 * (rho + 4.5 * cu * cu - 1.5 * usq)
        src_p = 2 * w4 * (9 * cu * (g * cx4) - 3 * g * ux)
        fp += wp * (eqp - fp) + (1 - 0.5 * wp) * src_p
        fm += wm * (6 * w4 * cu - fm) + (1 - 0.5 * wm) * (6 * g) * w4 * cx4
        post = np.empty_like(f)
        post[0] = f[0] + wp * (W[0] * (rho - 1.5 * usq) - f[0]) + (1 - 0.5 * wp) * W[0] * (-3 * g * ux)
        post[1:5] = 0.5 * (fp + fm)
        post[5:9] = 0.5 * (fp - fm)
        u_mean = float(np.dot(ux.ravel(), ch.fluid_flat)) / ch.n_fluid
        pf = post.reshape(-1)
        new = pf[ch.src]
        fix = ch.a * pf[ch.s1] + ch.b * pf[ch.s2]
        new[ch.dst] = fix
        # momentum given to the boundary by each link: c_k (f_post_k(x) + f_new_opp(k)(x))
        mom = ch.cxk * (pf[ch.out] + fix)
        f_plate = float(mom[ch.plate].sum())
        f_cyl = float(mom[ch.cyl].sum())
        if self.track_lift:                            # z force on the cylinder (zero when symmetric)
            self.lift = float(np.dot(ch.czk_cyl, (pf[ch.out] + fix)[ch.cyl]))
        new = new.reshape(9, ch.nx, ch.nz)
        if ch.cylinder:
            new[:, ch.solid] = W[:, None]              # solid nodes carry no information
        self.f = new
        return u_mean, f_plate, f_cyl


def solve(ch, re, u_target, f_init=None, block=500, g_tol=2e-7, check_steps=2000, max_steps=400000,
          kappa=0.02, log=print):
    """Steady flow at the target Reynolds number re with mean velocity u_target (lattice units).
    Returns a dict of results and the final populations."""
    n_d = ch.n_d
    nu = u_target * n_d / re
    h = ch.nz_full
    g0 = 12.0 * nu * u_target / h ** 2          # empty-channel body force for this mean velocity
    s = Solver(ch, nu, g0 * (3.0 if ch.cylinder else 1.0))
    if f_init is None:
        s.init_poiseuille(u_target)
        if not ch.symmetric:
            # an up-down asymmetric disturbance (1% of U): a steady symmetric end state then shows
            # that the symmetric solution is stable (no vortex shedding) at this Re
            x = (np.arange(ch.nx)[:, None] + 0.5) / ch.nx
            z = (np.arange(ch.nz)[None, :] + 0.5) / ch.nz_full
            uz = 0.01 * u_target * np.sin(2 * math.pi * x) * np.sin(math.pi * z)
            ux = np.broadcast_to(6.0 * u_target * z * (1 - z), uz.shape).copy()
            ux[ch.solid] = 0.0
            uz[ch.solid] = 0.0
            s.set_equilibrium(np.ones_like(ux), ux, uz)
    else:
        s.f[:] = f_init
    t0 = time.time()
    # controlled phase: g_{n+1} = (momentum lost to the boundaries in step n) / N_fluid + kappa (U* - U_n)
    steps, prev_block_g, g_sum = 0, None, 0.0
    converged = False
    while steps < max_steps:
        u, fp, fc = s.step()
        steps += 1
        s.g = (fp + fc) / ch.n_fluid + kappa * (u_target - u)
        g_sum += s.g
        if steps % block == 0:
            g_block = g_sum / block
            g_sum = 0.0
            if not np.isfinite(g_block):
                raise SystemExit("lbm_reference: diverged at Re %g, N %d" % (re, n_d))
            if prev_block_g is not None and abs(g_block - prev_block_g) < g_tol * abs(g_block):
                converged = True
                s.g = g_block
                break
            prev_block_g = g_block
    # check phase at fixed g: the mean velocity must be steady
    u_start = None
    acc = np.zeros(3)
    for n in range(check_steps):
        u, fp, fc = s.step()
        if u_start is None:
            u_start = u
        if n >= check_steps - block:
            acc += (u, fp, fc)
    u, fp, fc = s.step()
    steps += check_steps + 1
    rel_change = abs(u - u_start) / u
    _, fpb, fcb = acc / block
    total = s.g * ch.n_fluid
    rho, ux, uz = s.macros()
    umax = float(np.sqrt(ux ** 2 + uz ** 2)[ch.fluid].max())
    # relaxation time of the slowest (flux) mode of the channel, to turn the drift into a distance
    t_slow = h ** 2 / (math.pi ** 2 * nu)
    sym = 2 if ch.symmetric else 1                # the half channel carries half of every force
    f_cyl = sym * fcb
    res = dict(
        re=u * n_d / nu, re_target=re, resolution=n_d, domain="half" if ch.symmetric else "full",
        u_lat=u, nu_lat=nu, g_lat=s.g, umax_lat=umax,
        cd=2 * f_cyl / (u * u * n_d),
        cd_balance=2 * sym * (total - fpb) / (u * u * n_d),
        f_cylinder_fraction=fcb / total,
        f_plates_fraction=fpb / total,
        g_star=s.g * n_d ** 3 / nu ** 2,
        u_over_poiseuille=u / (s.g * h ** 2 / (12 * nu)),
        rel_change_u=rel_change, check_steps=check_steps,
        est_distance=rel_change * t_slow / check_steps,
        balance_residual=abs(total - fpb - fcb) / total,
        steps=steps, controlled_converged=converged,
        rho_mean=float(rho[ch.fluid].mean()), seconds=time.time() - t0,
    )
    res["cd_re"] = res["cd"] * res["re"]
    log("N=%d Re=%.3f U=%.5f Umax=%.4f Cd=%.5f Cd(bal)=%.5f CdRe=%.4f cyl=%.4f dU/U=%.1e "
        "bal=%.1e steps=%d %.0fs%s" % (n_d, res["re"], u, umax, res["cd"], res["cd_balance"], res["cd_re"],
                                       res["f_cylinder_fraction"], rel_change, res["balance_residual"],
                                       steps, res["seconds"], "" if converged else " (g NOT converged)"))
    return res, s.f.copy()


def poiseuille_check(log=print):
    """Empty channel (no cylinder), started from rest at fixed g: U must equal g h^2 / (12 nu)."""
    rows = []
    for n_d, nu in ((12, 1.0 / 6.0), (12, 0.5), (24, 0.5)):
        ch = Channel(n_d, cylinder=False, symmetric=False, nx=2)
        h = ch.nz_full
        g = 12 * nu * 0.03 / h ** 2
        s = Solver(ch, nu, g)
        s.set_equilibrium(np.ones((ch.nx, ch.nz)), np.zeros((ch.nx, ch.nz)), np.zeros((ch.nx, ch.nz)))
        t_slow = h ** 2 / (math.pi ** 2 * nu)
        steps = int(16 * t_slow)                   # e^-16 of the initial error left in the slowest mode
        for _ in range(steps):
            u, fp, fc = s.step()
        exact = g * h ** 2 / (12 * nu)
        rel = u / exact - 1
        # nodal values against the parabola g z (h - z) / (2 nu) at the node heights z = j + 1/2
        z = np.arange(ch.nz) + 0.5
        node_err = float(np.abs(s.macros()[1][0] / (g * z * (h - z) / (2 * nu)) - 1).max())
        rows.append((n_d, nu, steps, u, exact, rel, node_err))
        log("empty channel: h = %d nodes, nu = %.4f, %d steps from rest: U = %.8f, g h^2/(12 nu) = %.8f, "
            "relative error %.2e (node average; midpoint-rule term 1/(2 h^2) = %.2e); nodal profile max "
            "relative error %.1e" % (h, nu, steps, u, exact, rel, 0.5 / h ** 2, node_err))
    return rows


def stability(half_ch, half_f, res, steps, amplitude=1e-3, window=None, hold_u=False, avg_windows=1,
              kappa=0.02, log=print):
    """Linear stability of the mirror-symmetric steady state: the half-channel solution is mirrored
    into the whole channel, an up-down antisymmetric disturbance (vertical velocity amplitude *
    U near the cylinder) is added, and the flow runs at the same fixed body force. Returns the
    growth rate of the lift force per unit time d/U (negative: the disturbance decays, the
    symmetric steady flow is stable), the lift history and the mean C_D of the last avg_windows
    windows. hold_u: the body force follows the controller of solve() (mean velocity held at the
    steady value), to average the drag of a shedding flow at a given Re."""
    window = window or int(10 * half_ch.n_d / res["u_lat"])
    if steps < 4 * window:
        raise SystemExit("lbm_reference: --stability/--shedding need at least 4 windows of 10 d/U = %d steps, "
                         "got %d" % (4 * window, steps))
    ch = Channel(half_ch.n_d, symmetric=False)
    nzh = half_ch.nz
    f = np.empty((9, ch.nx, ch.nz))
    for k in range(9):
        f[k][:, :nzh] = half_f[k]
        f[k][:, nzh:] = half_f[MIRZ[k]][:, ::-1]
    u_t, nu = res["u_lat"], res["nu_lat"]
    x = np.arange(ch.nx)[:, None] + 0.5 - ch.xc
    z = np.arange(ch.nz)[None, :] + 0.5 - ch.zc
    duz = amplitude * u_t * np.exp(-((x - ch.n_d) ** 2 + z ** 2) / (2 * ch.n_d ** 2))   # even in z
    for k in range(9):
        f[k] += W[k] * 3 * CZ[k] * duz
    f[:, ch.solid] = W[:, None]
    s = Solver(ch, nu, res["g_lat"])
    s.f = f
    s.track_lift = True
    lift = np.empty(steps)
    drag = np.empty(steps)
    umean = np.empty(steps)
    for n in range(steps):
        u, fp, fc = s.step()
        lift[n] = s.lift
        drag[n] = fc
        umean[n] = u
        if hold_u:
            s.g = (fp + fc) / ch.n_fluid + kappa * (u_t - u)
    # envelope: largest |lift| in consecutive windows (a few shedding periods d / (0.2 U) long)
    t_unit = ch.n_d / u_t                           # steps per unit d / U
    nwin = steps // window
    env = np.array([np.abs(lift[i * window:(i + 1) * window]).max() for i in range(nwin)])
    tw = (np.arange(nwin) + 0.5) * window / t_unit
    half = nwin // 2
    rate = float(np.polyfit(tw[half:], np.log(env[half:]), 1)[0])
    last = slice(steps - avg_windows * window, steps)
    u_avg = float(umean[last].mean())
    cd_last = 2 * float(drag[last].mean()) / (u_avg * u_avg * ch.n_d)
    # shedding period from the upward zero crossings of the lift in the averaging interval
    lw = lift[last]
    up = np.nonzero((lw[:-1] < 0) & (lw[1:] >= 0))[0]
    st = (len(up) - 1) / ((up[-1] - up[0]) / t_unit) if len(up) > 2 else float("nan")
    log("stability N=%d Re=%.1f: lift envelope %s; growth rate %.4f per d/U over the last %d windows; "
        "over the last %d windows: U=%.5f (Re %.2f), C_D %.4f, C_D Re %.2f, Strouhal f d/U %.3f, "
        "lift amplitude C_L %.3f" % (ch.n_d, res["re"], " ".join("%.1e" % e for e in env), rate, nwin - half,
                                      avg_windows, u_avg, u_avg * ch.n_d / nu, cd_last,
                                      cd_last * u_avg * ch.n_d / nu, st,
                                      2 * float(np.abs(lw).max()) / (u_avg * u_avg * ch.n_d)))
    return rate, lift, cd_last


def equilibrium_from(ch, rho, ux, uz, scale=1.0):
    s = Solver(ch, 1.0 / 6.0)
    ux = ux * scale
    uz = uz * scale
    ux[ch.solid] = 0.0
    uz[ch.solid] = 0.0
    s.set_equilibrium(rho, ux, uz)
    return s.f


def refine(coarse_ch, coarse_f, fine_ch, scale=1.0):
    """Initial populations on a finer lattice: the coarse velocity field interpolated (bilinear,
    periodic in x), rescaled by `scale`, put in equilibrium."""
    from scipy.ndimage import map_coordinates
    cs = Solver(coarse_ch, 1.0 / 6.0)
    cs.f = coarse_f
    rho, ux, uz = cs.macros()
    r = fine_ch.n_d / coarse_ch.n_d
    i, j = np.meshgrid(np.arange(fine_ch.nx), np.arange(fine_ch.nz), indexing="ij")
    coords = [(i + 0.5) / r - 0.5, (j + 0.5) / r - 0.5]
    ux_f = map_coordinates(ux, coords, order=1, mode="grid-wrap")
    uz_f = map_coordinates(uz, coords, order=1, mode="grid-wrap")
    return equilibrium_from(fine_ch, np.ones_like(ux_f), ux_f, uz_f, scale)


def u_target_for(re, n_d, u_cap, nu_max):
    """Mean lattice velocity: as high as the Mach limit allows (u_cap), with nu <= nu_max."""
    return min(u_cap, re * nu_max / n_d)


FIELDS = ["re", "u", "cd", "cd_re", "f_cylinder_fraction", "resolution", "cd_balance", "f_plates_fraction",
          "g_star", "u_over_poiseuille", "re_target", "nu_lat", "g_lat", "umax_lat", "rel_change_u",
          "est_distance", "balance_residual", "steps", "seconds", "domain"]


def write_dense(rows, path):
    """C_D Re, C_D, the cylinder's share of the body force, U / U_Poiseuille and g* on a dense log Re
    grid: monotone cubic (PCHIP) interpolation in log Re of the finest resolution's points."""
    from scipy.interpolate import PchipInterpolator
    finest = sorted((r for r in rows if int(r["resolution"]) == max(int(q["resolution"]) for q in rows)),
                    key=lambda r: float(r["re"]))
    if len(finest) < 4:
        return
    lre = np.log([float(r["re"]) for r in finest])
    cols = ["cd_re", "f_cylinder_fraction", "u_over_poiseuille"]
    interp = {c: PchipInterpolator(lre, [float(r[c]) for r in finest]) for c in cols}
    log_g = PchipInterpolator(lre, np.log([float(r["g_star"]) for r in finest]))
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["re", "cd_re", "cd", "f_cylinder_fraction", "u_over_poiseuille", "g_star"])
        for lx in np.linspace(lre[0], lre[-1], 121):
            y = float(interp["cd_re"](lx))
            w.writerow(["%.5g" % math.exp(lx), "%.6g" % y, "%.6g" % (y / math.exp(lx)),
                        "%.6g" % float(interp["f_cylinder_fraction"](lx)),
                        "%.6g" % float(interp["u_over_poiseuille"](lx)), "%.6g" % math.exp(float(log_g(lx)))])
    print("wrote", path, "(N = %s)" % finest[0]["resolution"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--res", type=int, nargs="+", default=[12, 24], help="nodes per diameter (even)")
    ap.add_argument("--re", type=float, nargs="+", default=[0.5, 1, 2, 5, 10, 20, 30, 40])
    ap.add_argument("--u-cap", type=float, default=0.04, help="largest mean lattice velocity")
    ap.add_argument("--nu-max", type=float, default=0.5, help="largest lattice viscosity")
    ap.add_argument("--full", action="store_true", help="whole channel instead of the mirror half")
    ap.add_argument("--check", action="store_true", help="run the empty-channel Poiseuille check only")
    ap.add_argument("--out", default=os.path.join(HERE, "lbm_reference.csv"))
    ap.add_argument("--dense", default=os.path.join(HERE, "lbm_reference_dense.csv"),
                    help="C_D Re interpolated on a dense log Re grid (finest resolution)")
    ap.add_argument("--stability", type=int, metavar="STEPS",
                    help="no tables: for each --re (first --res) solve the half channel, then follow a small "
                         "antisymmetric disturbance in the whole channel for STEPS steps at fixed g")
    ap.add_argument("--shedding", type=int, metavar="STEPS",
                    help="like --stability with a 5%% disturbance and the mean velocity held: the time-averaged "
                         "C_D of the shedding flow over the last 80 d/U")
    ap.add_argument("--from-csv", action="store_true",
                    help="no solving: rewrite the dense table from the results file (--out)")
    args = ap.parse_args()
    if args.from_csv:
        with open(args.out) as fh:
            write_dense(list(csv.DictReader(fh)), args.dense)
        return
    if args.check:
        poiseuille_check()
        return
    if args.stability or args.shedding:
        ch = Channel(args.res[0])
        for re in args.re:
            res, f = solve(ch, re, u_target_for(re, args.res[0], args.u_cap, args.nu_max))
            if args.stability:
                stability(ch, f, res, args.stability)
            else:
                stability(ch, f, res, args.shedding, amplitude=0.05, hold_u=True, avg_windows=8)
        return
    for r in args.re:
        if r <= 0:
            raise SystemExit("lbm_reference: Reynolds numbers must be positive, got %g" % r)
    rows = []
    prev = {}                                    # resolution -> (channel, populations, u_target) of the last Re
    for n_d in sorted(args.res):
        ch = Channel(n_d, symmetric=not args.full)
        last = None
        for re in sorted(args.re):
            u_t = u_target_for(re, n_d, args.u_cap, args.nu_max)
            coarser = [m for m in prev if m < n_d and re in prev[m]]
            if coarser:                           # start from the coarser solution at the same Re
                m = max(coarser)
                cch, cf, cu = prev[m][re]
                f0 = refine(cch, cf, ch, u_t / cu)
            elif last is not None:                # or from the previous Re on this lattice
                s = Solver(ch, 1.0 / 6.0)
                s.f = last[0]
                f0 = equilibrium_from(ch, *s.macros(), scale=u_t / last[1])
            else:
                f0 = None
            res, f = solve(ch, re, u_t, f_init=f0)
            res["u"] = res["u_lat"]
            prev.setdefault(n_d, {})[re] = (ch, f, u_t)
            last = (f, u_t)
            res["re_target"] = re
            rows.append(res)
            sys.stdout.flush()
    with open(args.out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("%.6g" % v if isinstance(v, float) else v) for k, v in r.items()})
    print("wrote", args.out)
    if args.dense:
        write_dense(rows, args.dense)
    print("%-5s %-8s %-8s %-8s %-9s %-8s %s" % ("N", "Re", "U", "C_D", "C_D Re", "cyl frac", "dU/U"))
    for r in rows:
        print("%-5d %-8.3f %-8.5f %-8.4f %-9.3f %-8.4f %.1e" % (r["resolution"], r["re"], r["u"], r["cd"],
                                                               r["cd_re"], r["f_cylinder_fraction"],
                                                               r["rel_change_u"]))


if __name__ == "__main__":
    main()
