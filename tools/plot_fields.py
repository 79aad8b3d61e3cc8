#!/usr/bin/python3
# Draws the binned fields of a run ([analysis.fields], docs/config.md) as PNG pictures.
#
# Uses Debian's /usr/bin/python3 on purpose: it has matplotlib and numpy, the pyenv python3 on PATH
# does not. Matplotlib's Agg backend: no display needed.
#
# usage: tools/plot_fields.py FIELDS_CSV [--json FIELDS_JSON] [--out-dir DIR] [--prefix NAME]
#                             [--average-axis x|y|z] [--title TEXT] [--dpi N] [--min-density RHO]
#   FIELDS_CSV  <name>.csv written by mesodpd (columns ix,iy,iz,x,y,z,density,density_<species>...,
#               vx,vy,vz,temperature,temperature_x,temperature_y,temperature_z; one row per bin, x fastest)
#   --json      <name>.json beside it (default: same stem); its slab fit is drawn on a 1-D profile
#
# A 2-D grid (more than one bin along two axes) gives maps, as seed 004 Figs 4-7 and 9-10 show them:
#   <prefix>_density.png, <prefix>_v<a>.png for each velocity component, <prefix>_speed.png with
#   streamlines of the in-plane velocity, <prefix>_temperature.png.
# A 3-D grid is first averaged over --average-axis (default: the axis with the fewest bins); density
# is averaged plainly, velocity weighted by density, temperature by density.
# A 1-D grid gives <prefix>_profile.png: density (per species too), velocity components, temperature,
# with the slab fit of the JSON file when present.
import argparse
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

AXES = "xyz"
DPI = 150


def fail(message):
    print(f"plot_fields.py: error: {message}", file=sys.stderr)
    sys.exit(1)


def read_fields(path):
    """The CSV as {column: numpy array}, and the grid shape (nx, ny, nz)."""
    if not os.path.isfile(path):
        fail(f"file not found: {path}")
    try:
        data = np.genfromtxt(path, delimiter=",", names=True, dtype=float)
    except ValueError as e:
        fail(f"{path}: not a fields CSV ({e})")
    if data.dtype.names is None or data.size == 0:
        fail(f"{path} is empty")
    data = np.atleast_1d(data)
    required = ["ix", "iy", "iz", "x", "y", "z", "density", "vx", "vy", "vz", "temperature"]
    missing = [c for c in required if c not in data.dtype.names]
    if missing:
        fail(f"{path} lacks column(s) {', '.join(missing)}; has {', '.join(data.dtype.names)}")
    shape = tuple(int(data[c].max()) + 1 for c in ("ix", "iy", "iz"))
    if shape[0] * shape[1] * shape[2] != data.size:
        fail(f"{path}: {data.size} rows do not fill a {shape[0]} x {shape[1]} x {shape[2]} grid")
    columns = {}
    for name in data.dtype.names:
        # Rows are x fastest: reshape to [iz, iy, ix], then transpose to [ix, iy, iz].
        columns[name] = np.asarray(data[name], dtype=float).reshape(shape[2], shape[1], shape[0]).transpose(2, 1, 0)
    return columns, shape


def average_over(columns, axis):
    """Averages every field over one axis: density plainly, the others weighted by the density."""
    rho = columns["density"]
    weight = np.where(np.isfinite(rho), rho, 0.0)
    wsum = weight.sum(axis=axis, keepdims=True)
    out = {}
    for name, values in columns.items():
        if name.startswith("density") or name in ("ix", "iy", "iz", "x", "y", "z"):
            out[name] = np.nanmean(values, axis=axis, keepdims=True)
        else:
            filled = np.where(np.isfinite(values), values, 0.0)
            with np.errstate(invalid="ignore", divide="ignore"):
                out[name] = (filled * weight).sum(axis=axis, keepdims=True) / wsum
    return out


def species_columns(columns):
    return [c for c in columns if c.startswith("density_")]


def draw_map(path, title, a, b, xa, xb, values, label, cmap="viridis", streams=None, symmetric=False):
    """One colour map over the (a, b) plane; `streams` = (ua, ub) adds streamlines."""
    extent_a = (xa[0] - 0.5 * (xa[1] - xa[0]) if len(xa) > 1 else xa[0] - 0.5, xa[-1] + 0.5 * (xa[1] - xa[0]) if len(xa) > 1 else xa[0] + 0.5)
    extent_b = (xb[0] - 0.5 * (xb[1] - xb[0]) if len(xb) > 1 else xb[0] - 0.5, xb[-1] + 0.5 * (xb[1] - xb[0]) if len(xb) > 1 else xb[0] + 0.5)
    width = extent_a[1] - extent_a[0]
    height = extent_b[1] - extent_b[0]
    aspect = height / width if width > 0 else 1.0
    fig_w = 7.0
    fig, ax = plt.subplots(figsize=(fig_w, max(2.5, min(9.0, fig_w * aspect + 1.0))))
    masked = np.ma.masked_invalid(values.T)  # rows: b, columns: a
    limits = {}
    if symmetric and masked.count() > 0:  # a diverging map with white at zero
        top = float(np.max(np.abs(masked)))
        limits = {"vmin": -top, "vmax": top}
    image = ax.imshow(masked, origin="lower", extent=(*extent_a, *extent_b), cmap=cmap, aspect="equal",
                      interpolation="nearest", **limits)
    fig.colorbar(image, ax=ax, label=label, shrink=0.85)
    if streams is not None and len(xa) > 1 and len(xb) > 1:
        ua = np.ma.masked_invalid(streams[0].T)
        ub = np.ma.masked_invalid(streams[1].T)
        ax.streamplot(xa, xb, ua.filled(np.nan), ub.filled(np.nan), color="white", linewidth=0.7, density=1.4,
                      arrowsize=0.8)
        ax.set_xlim(*extent_a)
        ax.set_ylim(*extent_b)
    ax.set_xlabel(AXES[a])
    ax.set_ylabel(AXES[b])
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def plot_maps(columns, shape, out_dir, prefix, title):
    plane = [d for d in range(3) if shape[d] > 1]
    if len(plane) == 1:  # a 2-D grid with one axis of one bin left after averaging: not a map
        return []
    a, b = plane
    squeeze = tuple(d for d in range(3) if d not in plane)

    def field(name):
        return np.squeeze(columns[name], axis=squeeze)

    xa = field(AXES[a])[:, 0]
    xb = field(AXES[b])[0, :]
    written = []
    head = f"{title}: " if title else ""
    written.append(draw_map(os.path.join(out_dir, f"{prefix}_density.png"), f"{head}number density", a, b, xa, xb,
                            field("density"), "density"))
    for d in range(3):
        written.append(draw_map(os.path.join(out_dir, f"{prefix}_v{AXES[d]}.png"), f"{head}velocity v_{AXES[d]}", a, b,
                                xa, xb, field(f"v{AXES[d]}"), f"v_{AXES[d]}", cmap="RdBu_r", symmetric=True))
    ua, ub = field(f"v{AXES[a]}"), field(f"v{AXES[b]}")
    written.append(draw_map(os.path.join(out_dir, f"{prefix}_speed.png"),
                            f"{head}in-plane speed and streamlines", a, b, xa, xb, np.hypot(ua, ub),
                            f"|(v_{AXES[a]}, v_{AXES[b]})|", cmap="magma", streams=(ua, ub)))
    written.append(draw_map(os.path.join(out_dir, f"{prefix}_temperature.png"), f"{head}temperature", a, b, xa, xb,
                            field("temperature"), "k_B T", cmap="inferno"))
    return written


def slab_curve(z, fit, period):
    d = z - fit["z0"]
    if period:
        d = d - period * np.round(d / period)
    return 0.5 * (fit["rho_l"] + fit["rho_v"]) - 0.5 * (fit["rho_l"] - fit["rho_v"]) * np.tanh(
        (np.abs(d) - fit["half_width"]) / fit["width"])


def plot_profile(columns, shape, meta, out_dir, prefix, title):
    axis = [d for d in range(3) if shape[d] > 1]
    axis = axis[0] if axis else 2
    z = columns[AXES[axis]].reshape(-1)
    order = np.argsort(z)
    z = z[order]

    def col(name):
        return columns[name].reshape(-1)[order]

    fig, (ax_rho, ax_v, ax_t) = plt.subplots(3, 1, figsize=(7, 9), sharex=True)
    ax_rho.plot(z, col("density"), "o-", ms=3, label="density (selected species)")
    species = species_columns(columns)
    if len(species) > 1:
        for name in species:
            ax_rho.plot(z, col(name), "-", lw=1, label=name.replace("_", " "))
    fit = (meta or {}).get("slab_fit")
    if fit and fit.get("rho_l") is not None:
        period = fit.get("period") or 0.0
        zz = np.linspace(z[0], z[-1], 400)
        ax_rho.plot(zz, slab_curve(zz, fit, period), "r-", lw=1.2,
                    label=(f"tanh fit: ρ_l = {fit['rho_l']:.4g}, ρ_v = {fit['rho_v']:.3g}, "
                           f"w = {fit['width']:.3g}"))
    ax_rho.set_ylabel("number density")
    ax_rho.legend(fontsize=8)
    for d in range(3):
        ax_v.plot(z, col(f"v{AXES[d]}"), "-", label=f"v_{AXES[d]}")
    ax_v.set_ylabel("velocity")
    ax_v.legend(fontsize=8)
    ax_t.plot(z, col("temperature"), "k-", label="T")
    for d in range(3):
        name = f"temperature_{AXES[d]}"
        if name in columns:
            ax_t.plot(z, col(name), ":", lw=1, label=f"T_{AXES[d]}")
    ax_t.set_ylabel("k_B T")
    ax_t.set_xlabel(AXES[axis])
    ax_t.legend(fontsize=8)
    if title:
        ax_rho.set_title(title)
    fig.tight_layout()
    path = os.path.join(out_dir, f"{prefix}_profile.png")
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return [path]


def main(argv=None):
    parser = argparse.ArgumentParser(description="PNG maps and profiles of mesodpd binned fields")
    parser.add_argument("csv", help="<name>.csv written by [analysis.fields]")
    parser.add_argument("--json", help="<name>.json (default: beside the CSV)")
    parser.add_argument("--out-dir", help="where the PNGs go (default: the CSV's directory)")
    parser.add_argument("--prefix", help="file name prefix (default: the CSV's stem)")
    parser.add_argument("--average-axis", choices=list(AXES), help="for a 3-D grid: the axis averaged over")
    parser.add_argument("--title", default="", help="text put in front of each picture's title")
    parser.add_argument("--dpi", type=int, default=150, help="resolution of the PNGs (default 150)")
    parser.add_argument("--min-density", type=float, default=0.0,
                        help="leave bins whose density is below this blank in the velocity, speed and temperature "
                             "maps (bins cut by a solid hold few particles and noisy means; default 0: none)")
    args = parser.parse_args(argv)
    global DPI
    DPI = args.dpi
    stem = os.path.splitext(args.csv)[0]
    out_dir = args.out_dir or os.path.dirname(os.path.abspath(args.csv))
    prefix = args.prefix or os.path.basename(stem)
    os.makedirs(out_dir, exist_ok=True)
    columns, shape = read_fields(args.csv)
    meta = None
    json_path = args.json or stem + ".json"
    if os.path.isfile(json_path):
        with open(json_path) as handle:
            meta = json.load(handle)
    elif args.json:
        fail(f"file not found: {args.json}")
    dims = [d for d in range(3) if shape[d] > 1]
    if len(dims) == 3:
        axis = AXES.index(args.average_axis) if args.average_axis else int(np.argmin(shape))
        columns = average_over(columns, axis)
        shape = tuple(1 if d == axis else shape[d] for d in range(3))
        dims = [d for d in range(3) if shape[d] > 1]
    if args.min_density > 0:
        thin = ~(columns["density"] >= args.min_density)
        for name in columns:
            if not name.startswith("density") and name not in ("ix", "iy", "iz", "x", "y", "z"):
                columns[name] = np.where(thin, np.nan, columns[name])
    if len(dims) == 2:
        written = plot_maps(columns, shape, out_dir, prefix, args.title)
    else:
        written = plot_profile(columns, shape, meta, out_dir, prefix, args.title)
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
