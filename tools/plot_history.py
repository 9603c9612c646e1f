#!/usr/bin/python3
"""Plot a spall run's history.csv: energies, relative energy error, momentum and time step.

Usage: tools/plot_history.py OUTDIR [--out PNG]
"""
import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless: no display on build or cluster nodes
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent / "python"))
import spall  # noqa: E402  (tools/python/spall: the readers of spall's output)

REQUIRED = ["step", "time", "dt", "kinetic_energy", "internal_energy", "total_energy",
            "momentum_x", "momentum_y", "momentum_z"]


def read_history(path):
    """Return a dict column -> float array. Extra columns are allowed (docs/reference.md)."""
    table = spall.read_csv(path)
    if len(table) == 0:
        raise ValueError(f"{path}: no data rows")
    missing = [c for c in REQUIRED if c not in table]
    if missing:
        raise ValueError(f"{path}: missing column(s) {', '.join(missing)}")
    cols = {name: table[name].astype(float) for name in table}
    # A restarted run re-writes the steps after the checkpoint: keep the last row for each step.
    _, last = np.unique(cols["step"][::-1], return_index=True)
    keep = np.sort(len(cols["step"]) - 1 - last)
    return {k: v[keep] for k, v in cols.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("outdir", type=Path, help="spall output directory (holds history.csv)")
    ap.add_argument("--out", type=Path, help="PNG to write (default: OUTDIR/history.png)")
    args = ap.parse_args()

    path = args.outdir / "history.csv"
    if not path.is_file():
        ap.error(f"{path} not found (is {args.outdir} a spall output directory?)")
    try:
        h = read_history(path)
    except ValueError as e:
        ap.error(str(e))
    t = h["time"]

    fig, ax = plt.subplots(2, 2, figsize=(11, 7.5), sharex=True)
    a = ax[0, 0]
    a.plot(t, h["total_energy"], "k-", label="total")
    a.plot(t, h["kinetic_energy"], label="kinetic")
    a.plot(t, h["internal_energy"], label="internal")
    a.set_ylabel("energy [J]")
    a.legend()

    a = ax[0, 1]
    e0 = h["total_energy"][0]
    # Guard E0 = 0 (e.g. a deck that starts at rest with zero internal energy): scale by the
    # largest energy seen instead, so the curve stays a relative error.
    scale = abs(e0) if e0 != 0 else max(np.abs(h["total_energy"]).max(), 1e-300)
    a.plot(t, (h["total_energy"] - e0) / scale, "k-")
    a.set_ylabel("(E - E0) / |E0|")
    a.ticklabel_format(axis="y", style="sci", scilimits=(-2, 2))

    a = ax[1, 0]
    for c in "xyz":
        p = h[f"momentum_{c}"]
        # Components that are identically zero (lower-dimensional runs) only add clutter.
        if c == "x" or np.any(p != 0):
            a.plot(t, p, label=f"p_{c}")
    a.set_ylabel("momentum [kg m/s]")
    a.legend()

    a = ax[1, 1]
    a.semilogy(t, h["dt"], "k-")
    a.set_ylabel("dt [s]")

    for a in ax[1]:
        a.set_xlabel("time [s]")
    for a in ax.flat:
        a.grid(alpha=0.3)
    fig.suptitle(f"{args.outdir}: {len(t)} rows, steps {int(h['step'][0])}-{int(h['step'][-1])}")
    fig.tight_layout()
    out = args.out or args.outdir / "history.png"
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    sys.exit(main())
