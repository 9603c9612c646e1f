#!/usr/bin/python3
"""Plot the fragment catalogue of a spall run (fragments.csv, written when the deck has a
[fragments] table): the cumulative mass distribution, the fraction of the total mass in fragments
of mass M or more against M (Owen 2010, Figs. 12, 16 and 21 style), one line per output time, and
print the largest fragments of the last time.

Examples:
  tools/plot_fragments.py out/rock_impact_2d                   # every output time, PNG beside it
  tools/plot_fragments.py out/rock_impact_2d --times 8e-6 1.2e-5 --png frags.png
  tools/plot_fragments.py out/rock_impact_2d --min-particles 2  # lone particles left out
"""
import argparse
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless: no display on build or cluster nodes
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent / "python"))
import spall  # noqa: E402  (tools/python/spall: the readers of spall's output)


def read_catalogue(path):
    """{time: list of (particles, mass)} in the file's order (largest first)."""
    out = defaultdict(list)
    t = spall.read_csv(path)
    for time, n, m in zip(t["time"], t["particles"], t["mass"]):
        out[float(time)].append((int(n), float(m)))
    return dict(sorted(out.items()))


def cumulative(fragments, min_particles):
    """Masses (descending) and the fraction of the total mass in fragments at least that heavy."""
    total = sum(m for _, m in fragments)
    masses = np.array([m for n, m in fragments if n >= min_particles])
    if masses.size == 0:
        return masses, masses
    masses = np.sort(masses)[::-1]
    return masses, np.cumsum(masses) / total


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run", type=Path, help="the run's output directory (or its fragments.csv)")
    ap.add_argument("--times", type=float, nargs="*", help="output times to draw (nearest; "
                    "default: all, at most 8 evenly spread)")
    ap.add_argument("--min-particles", type=int, default=1,
                    help="leave out fragments of fewer particles (default 1: all)")
    ap.add_argument("--png", type=Path, help="output file (default: RUN/fragments.png)")
    args = ap.parse_args(argv)

    path = args.run if args.run.suffix == ".csv" else args.run / "fragments.csv"
    if not path.exists():
        print(f"error: {path} does not exist (does the deck have a [fragments] table?)",
              file=sys.stderr)
        return 2
    catalogue = read_catalogue(path)
    if not catalogue:
        print(f"error: {path} has no rows", file=sys.stderr)
        return 2
    times = list(catalogue)
    if args.times:
        chosen = sorted({min(times, key=lambda t: abs(t - want)) for want in args.times})
    else:
        picks = np.unique(np.linspace(0, len(times) - 1, min(8, len(times))).round().astype(int))
        chosen = [times[k] for k in picks]

    fig, ax = plt.subplots(figsize=(7, 5))
    for t in chosen:
        masses, fraction = cumulative(catalogue[t], args.min_particles)
        if masses.size:
            ax.step(masses, fraction, where="post", label=f"t = {t * 1e6:.3g} us "
                    f"({len(catalogue[t])} fragments)")
    ax.set_xscale("log")
    ax.set_xlabel("fragment mass M (kg, or kg/m in 2D, kg/m^2 in 1D)")
    ax.set_ylabel("fraction of the mass in fragments of mass >= M")
    ax.set_ylim(0.0, 1.02)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Cumulative fragment mass: {path.parent.name}")
    png = args.png or path.parent / "fragments.png"
    fig.tight_layout()
    fig.savefig(png, dpi=120)

    last = times[-1]
    frags = catalogue[last]
    total = sum(m for _, m in frags)
    print(f"t = {last:.6g} s: {len(frags)} fragments, {sum(n >= 10 for n, _ in frags)} of 10 "
          f"particles or more; the largest:")
    for k, (n, m) in enumerate(frags[:5]):
        print(f"  {k}: {n} particles, {m:.6g} ({m / total * 100:.2f}% of the mass)")
    print(f"wrote {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
