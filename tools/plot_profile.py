#!/usr/bin/python3
# Plots a reverse-Poiseuille velocity profile (CSV z,v_mean,v_err,v_fit) with its viscosity summary as a PNG.
#
# Uses Debian's /usr/bin/python3 on purpose: it has matplotlib and numpy, the pyenv python3 on PATH
# does not.
#
# usage: tools/plot_profile.py PROFILE_CSV SUMMARY_CSV [-o OUT.png]
#   PROFILE_CSV  written by PoiseuilleProfile::write_csv (columns z,v_mean,v_err,v_fit)
#   SUMMARY_CSV  written by write_viscosity_summary_csv (eta,eta_err,v_amplitude,blocks_used,eta_kinetic)
import argparse
import csv
import math
import os
import sys


def fail(message):
    print(f"plot_profile.py: error: {message}", file=sys.stderr)
    sys.exit(1)


def read_columns(path, required):
    """Reads a CSV with a header row into {column: [float, ...]}; fails clearly on missing columns."""
    if not os.path.isfile(path):
        fail(f"file not found: {path}")
    with open(path, newline="") as handle:
        reader = csv.DictReader(handle)
        if reader.fieldnames is None:
            fail(f"{path} is empty")
        missing = [c for c in required if c not in reader.fieldnames]
        if missing:
            fail(f"{path} lacks column(s) {', '.join(missing)}; has {', '.join(reader.fieldnames)}")
        columns = {name: [] for name in reader.fieldnames}
        for line_no, row in enumerate(reader, start=2):
            for name in reader.fieldnames:
                try:
                    columns[name].append(float(row[name]))
                except (TypeError, ValueError):
                    fail(f"{path}:{line_no}: column {name} is not a number: {row[name]!r}")
    return columns


def summary_text(summary):
    """One annotation line, e.g. 'eta = 0.85 ± 0.01 (kinetic theory 0.96)'."""
    eta = summary["eta"][0]
    text = f"η = {eta:.4g}"
    err = summary.get("eta_err", [math.nan])[0]
    if math.isfinite(err):
        text += f" ± {err:.2g}"
    kinetic = summary.get("eta_kinetic", [math.nan])[0]
    if math.isfinite(kinetic):
        text += f"  (kinetic theory {kinetic:.4g})"
    blocks = summary.get("blocks_used", [math.nan])[0]
    if math.isfinite(blocks):
        text += f",  {int(blocks)} blocks"
    return text


def main():
    parser = argparse.ArgumentParser(description="Plot a reverse-Poiseuille profile and its fitted viscosity.")
    parser.add_argument("profile", help="profile CSV with columns z,v_mean,v_err,v_fit")
    parser.add_argument("summary", help="viscosity summary CSV with at least column eta")
    parser.add_argument("-o", "--output", help="PNG to write (default: PROFILE with .png)")
    args = parser.parse_args()

    profile = read_columns(args.profile, ["z", "v_mean", "v_err", "v_fit"])
    summary = read_columns(args.summary, ["eta"])
    if not profile["z"]:
        fail(f"{args.profile} has no data rows")
    if not summary["eta"]:
        fail(f"{args.summary} has no data rows")
    output = args.output or os.path.splitext(args.profile)[0] + ".png"

    try:
        import matplotlib

        matplotlib.use("Agg")  # no display on build and compute machines
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError as exc:
        fail(f"needs matplotlib and numpy ({exc}); run with /usr/bin/python3")

    z = np.asarray(profile["z"])
    v = np.asarray(profile["v_mean"])
    err = np.asarray(profile["v_err"])
    fit = np.asarray(profile["v_fit"])
    err = np.where(np.isfinite(err), err, 0.0)  # fewer than two blocks: no bars

    fig, ax = plt.subplots(figsize=(7.2, 4.8))
    ax.errorbar(z, v, yerr=err, fmt="o", ms=3.5, capsize=2, label="measured")
    ax.plot(z, fit, "-", color="black", lw=1.2, label="fit: reverse Poiseuille")
    ax.set_xlabel("z (gradient coordinate)")
    ax.set_ylabel("mean flow velocity")
    ax.set_title("Reverse Poiseuille flow")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right")
    fig.text(0.5, 0.01, summary_text(summary), ha="center", va="bottom")
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    try:
        fig.savefig(output, dpi=120)
    except OSError as exc:
        fail(f"cannot write {output}: {exc}")
    print(output)


if __name__ == "__main__":
    main()
