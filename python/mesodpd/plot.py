"""matplotlib versions of the pictures the command line draws (velocity_profile.svg) and of the
other results: thermo history, g(r), MSD. Each function takes a Simulation or the dict its method
returns, draws on ``ax`` (a new figure when None), saves to ``path`` when given, and returns the
figure."""
import matplotlib

if matplotlib.get_backend().lower() not in ("agg", "pdf", "svg", "ps", "cairo") and not __import__("os").environ.get(
        "DISPLAY"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["velocity_profile", "thermo", "rdf", "msd", "fields"]


def _axes(ax):
    if ax is None:
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        return fig, ax
    return ax.figure, ax


def _finish(fig, path):
    if path is not None:
        fig.savefig(path, bbox_inches="tight")
    return fig


def velocity_profile(data, ax=None, path=None):
    """Reverse-Poiseuille flow: measured mean velocity per bin with error bars and the parabolic fit, as
    in velocity_profile.svg. ``data``: a Simulation or Simulation.profile()."""
    p = data.profile() if hasattr(data, "profile") else data
    if p is None:
        raise ValueError("no velocity profile: the spec has no [poiseuille] section")
    fig, ax = _axes(ax)
    axes = "xyz"
    err = np.where(np.isfinite(p["v_err"]), p["v_err"], 0.0)
    ax.errorbar(p["z"], p["v_mean"], yerr=err, fmt="o", ms=3, color="#1f77b4", label="measured")
    ax.plot(p["z"], p["v_fit"], "--", color="#d62728", label="parabolic fit")
    ax.set_xlabel(f"{axes[p['gradient_axis']]} (gradient axis)")
    ax.set_ylabel(f"mean v_{axes[p['flow_axis']]}")
    ax.set_title(f"Reverse Poiseuille flow: eta = {p['eta']:.4f} +- {p['eta_err']:.4f}")
    ax.legend()
    return _finish(fig, path)


def thermo(data, keys=("temperature", "pressure"), ax=None, path=None):
    """Thermo columns against time. ``data``: a Simulation or Simulation.thermo_history()."""
    h = data.thermo_history() if hasattr(data, "thermo_history") else data
    fig, ax = _axes(ax)
    for k in keys:
        ax.plot(h["time"], h[k], label=k)
    ax.set_xlabel("time")
    ax.legend()
    return _finish(fig, path)


def rdf(data, ax=None, path=None):
    """g(r). ``data``: a Simulation or Simulation.rdf() (or any dict with r and g)."""
    g = data.rdf() if hasattr(data, "rdf") else data
    if g is None:
        raise ValueError("no RDF: the spec has no [analysis.rdf] section")
    fig, ax = _axes(ax)
    ax.plot(g["r"], g["g"])
    ax.axhline(1.0, color="gray", lw=0.5)
    ax.set_xlabel("r")
    ax.set_ylabel("g(r)")
    return _finish(fig, path)


def msd(data, ax=None, path=None):
    """Mean squared displacement against lag time. ``data``: a Simulation or Simulation.msd()."""
    m = data.msd() if hasattr(data, "msd") else data
    if m is None:
        raise ValueError("no MSD: the spec has no [analysis.msd] section")
    fig, ax = _axes(ax)
    ax.plot(m["time"], m["msd"], label="MSD")
    if np.isfinite(m.get("diffusion", np.nan)):
        ax.plot(m["time"], 6 * m["diffusion"] * np.asarray(m["time"]), "--", label=f"6 D t, D = {m['diffusion']:.4f}")
    ax.set_xlabel("lag time")
    ax.set_ylabel("MSD")
    ax.legend()
    return _finish(fig, path)


def fields(data, name=None, quantity="density", ax=None, path=None, arrows=True):
    """An [analysis.fields] grid: a colour map of ``quantity`` (density, vx, vy, vz, temperature) for a 2-D
    grid, with the in-plane velocity as arrows (like the command line's SVG maps), or a profile for a
    1-D grid. ``data``: a Simulation or Simulation.fields(); ``name``: the grid (the only one if None)."""
    grids = data.fields() if hasattr(data, "fields") else data
    if not grids:
        raise ValueError("no binned fields: the spec has no [analysis.fields] section")
    if name is None:
        if len(grids) > 1:
            raise ValueError(f"several grids ({', '.join(grids)}): pass name=")
        name = next(iter(grids))
    f = grids[name]
    if f["samples"] == 0:
        raise ValueError(f"grid {name!r} has no samples yet")
    axes = [d for d in range(3) if f["bins"][d] > 1]
    labels = "xyz"
    coords = (f["x"], f["y"], f["z"])
    values = np.squeeze(f[quantity])
    fig, ax = _axes(ax)
    if len(axes) == 1:
        d = axes[0]
        ax.plot(np.squeeze(coords[d]), values, "o-", ms=3)
        ax.set_xlabel(labels[d])
        ax.set_ylabel(quantity)
    elif len(axes) == 2:
        a, b = axes
        ca, cb = np.squeeze(coords[a]), np.squeeze(coords[b])
        mesh = ax.pcolormesh(ca, cb, values, shading="nearest", cmap="viridis")
        fig.colorbar(mesh, ax=ax, label=quantity)
        if arrows:
            va, vb = np.squeeze(f["v" + labels[a]]), np.squeeze(f["v" + labels[b]])
            ax.quiver(ca, cb, va, vb, color="white")
        ax.set_xlabel(labels[a])
        ax.set_ylabel(labels[b])
        ax.set_aspect("equal")
    else:
        raise ValueError(f"grid {name!r} has bins {f['bins']}: plot a 1-D or 2-D grid")
    ax.set_title(f"{name}: {quantity} ({f['samples']} samples)")
    return _finish(fig, path)
