#!/usr/bin/env python3
"""Plots cost per particle-step against N from bench_fluid output (docs/performance.md).

Input: lines "<label> <repetition> <bench_fluid table row>", as written by bench/scaling.sh; the best
(fastest) repetition of each (label, N, threads) is plotted.

    /usr/bin/python3 bench/plot_scaling.py bench/results/scaling-2026-11-28.txt docs/performance_scaling.svg
"""
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text: a small, diffable file
import matplotlib.pyplot as plt  # noqa: E402


def read_best(path):
    best = defaultdict(lambda: float("inf"))  # (label, threads) -> {N: ns}
    for line in open(path):
        cols = line.split()
        if len(cols) < 8 or not cols[2].isdigit():
            continue
        label, n, threads, ns = cols[0], int(cols[2]), int(cols[4]), float(cols[7])
        best[(label, threads, n)] = min(best[(label, threads, n)], ns)
    series = defaultdict(dict)
    for (label, threads, n), ns in best.items():
        series[(label, threads)][n] = ns
    return series


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_scaling.py RESULTS.txt OUT.svg")
    series = read_best(sys.argv[1])
    names = {"build": "double", "build-single": "single (MESODPD_SINGLE)"}
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for (label, threads), points in sorted(series.items()):
        ns = sorted(points)
        style = "-" if label == "build" else "--"
        ax.plot(ns, [points[n] for n in ns], style, marker="o",
                label=f"{names.get(label, label)}, {threads} thread{'s' if threads > 1 else ''}")
    ax.set_xscale("log")
    ax.set_ylim(bottom=0)
    ax.set_xlabel("particles N")
    ax.set_ylabel("wall time per particle-step (ns)")
    ax.set_title("Standard DPD fluid (rho = 3, dt = 0.04): cost per particle-step")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(sys.argv[2])


if __name__ == "__main__":
    main()
