#!/usr/bin/python3
"""Plot a spall run's probes.csv: one panel per field, one line per probe.

Example (Lam, Shen & Gong 2001 Fig. 3: stress history at the striker middle):
  tools/plot_probes.py out/rod_impact --probe striker_mid --field stress_xx \\
      --time-unit us --scale-stress MPa
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

TIME_UNITS = {"s": 1.0, "ms": 1e3, "us": 1e6}
STRESS_UNITS = {"Pa": 1.0, "kPa": 1e-3, "MPa": 1e-6, "GPa": 1e-9}


def si_unit(field):
    """The SI unit of the probe fields docs/reference.md names; '' for fields a later model adds."""
    if field.startswith("velocity_"):
        return "m/s"
    if field.startswith("position_"):
        return "m"
    return {"density": "kg/m^3", "specific_internal_energy": "J/kg"}.get(field, "")


def is_stress(field):
    """Fields carrying Pa: stress components and pressure (scaled by --scale-stress)."""
    return field.startswith("stress") or field == "pressure"


def read_probes(path):
    """Return {(probe, field): (time array, value array)}, sorted by time."""
    series = defaultdict(list)
    t = spall.read_csv(path)  # ValueError naming the line of a malformed row
    missing = {"time", "probe", "field", "value"} - set(t.names())
    if missing:
        raise ValueError(f"{path}: missing column(s) {', '.join(sorted(missing))}")
    if t["time"].dtype.kind not in "fi" or (len(t) and t["value"].dtype.kind not in "fi"):
        raise ValueError(f"{path}: a time or value that is not a number")
    for time, probe, field, value in zip(t["time"], t["probe"], t["field"], t["value"]):
        series[str(probe), str(field)].append((float(time), float(value)))
    out = {}
    for key, samples in series.items():
        a = np.array(sorted(samples))  # rank 0 may gather samples out of order
        out[key] = a[:, 0], a[:, 1]
    return out


def select(requested, available, what, ap):
    """Keep the requested names (in the order given) or all; unknown names are usage errors."""
    if not requested:
        return sorted(available)
    unknown = [r for r in requested if r not in available]
    if unknown:
        ap.error(f"unknown {what} {', '.join(unknown)}; available: {', '.join(sorted(available))}")
    return list(dict.fromkeys(requested))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0], epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outdir", type=Path, help="spall output directory (holds probes.csv)")
    ap.add_argument("--probe", nargs="+", action="extend", help="probe name(s) to plot (default: all)")
    ap.add_argument("--field", nargs="+", action="extend", help="field(s) to plot (default: all)")
    ap.add_argument("--out", type=Path, help="PNG to write (default: OUTDIR/probes.png)")
    ap.add_argument("--time-unit", choices=TIME_UNITS, default="s")
    ap.add_argument("--scale-stress", choices=STRESS_UNITS, default="Pa",
                    help="unit for stress_* and pressure fields (default: Pa)")
    args = ap.parse_args()

    path = args.outdir / "probes.csv"
    if not path.is_file():
        ap.error(f"{path} not found (does the deck define [[probe]]s?)")
    try:
        data = read_probes(path)
    except ValueError as e:
        ap.error(str(e))
    if not data:
        ap.error(f"{path}: no samples")
    probes = select(args.probe, {p for p, _ in data}, "probe", ap)
    fields = select(args.field, {f for _, f in data}, "field", ap)

    tscale, sscale = TIME_UNITS[args.time_unit], STRESS_UNITS[args.scale_stress]
    fig, axes = plt.subplots(len(fields), 1, figsize=(8, 2.6 + 2.2 * len(fields)), sharex=True,
                             squeeze=False)
    for ax, field in zip(axes[:, 0], fields):
        unit = args.scale_stress if is_stress(field) else si_unit(field)
        for probe in probes:
            if (probe, field) in data:  # not every probe samples every field
                t, v = data[probe, field]
                ax.plot(t * tscale, v * (sscale if is_stress(field) else 1.0), label=probe)
        ax.set_ylabel(f"{field} [{unit}]" if unit else field)
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small")
    axes[-1, 0].set_xlabel(f"time [{args.time_unit}]")
    fig.suptitle(str(args.outdir))
    fig.tight_layout()
    out = args.out or args.outdir / "probes.png"
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    sys.exit(main())
