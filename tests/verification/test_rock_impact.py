#!/usr/bin/python3
"""The fragment catalogue of a shattering rock (decks/rock_impact_2d.toml; issue 15), on 2 ranks,
checked against the particles it describes at every output time:
- the fragments' masses sum to the particles' mass and their momenta to the particles' momentum
  (relative 1e-12: the same numbers summed in another order);
- each particle's `fragment` is its place in the list: the particles carrying index k number
  `particles` of row k and weigh its mass;
- the list is ordered by mass, largest first;
- a fragment of two or more particles holds no particle at or above the damage threshold;
and the physics the deck's header states: at 2 us the failed particles lie on the impact side
(mean height above the centre), and by the end the target has shattered (largest fragment under
half of the mass, at least 5 fragments of 10 particles or more).

usage: test_rock_impact.py SPALL SOURCE_DIR
"""
import csv
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import h5py
import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
DECK = SRC / "decks" / "rock_impact_2d.toml"
THRESHOLD = 0.95
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


with tempfile.TemporaryDirectory() as tmp:
    out = Path(tmp) / "rock"
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", SPALL, "run", str(DECK),
           "--output", str(out), "--quiet"]
    p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    if p.returncode != 0:
        print(p.stderr[-3000:])
        sys.exit(1)
    rows = defaultdict(list)
    with open(out / "fragments.csv", newline="") as f:
        for r in csv.DictReader(f):
            rows[float(r["time"])].append(r)
    snaps = sorted((out / "snapshots").glob("snap_*.h5"))
    check(len(rows) == len(snaps), f"one catalogue per snapshot ({len(rows)} and {len(snaps)})")
    worst_mass = worst_momentum = 0.0
    bad_index = bad_order = bad_members = 0
    last = None
    for snap in snaps:
        with h5py.File(snap, "r") as f:
            g = f["particles"]
            t = float(f.attrs["time"])
            m, v, frag, D = g["mass"][()], g["velocity"][()], g["fragment"][()], g["damage"][()]
            y, body = g["position"][()][:, 1], g["body"][()]
        cat = rows.get(t, [])
        mass = np.array([float(r["mass"]) for r in cat])
        count = np.array([int(r["particles"]) for r in cat])
        mom = np.array([[float(r["vx"]), float(r["vy"])] for r in cat]) * mass[:, None]
        worst_mass = max(worst_mass, abs(mass.sum() - m.sum()) / m.sum())
        scale = np.abs(m[:, None] * v).sum()
        worst_momentum = max(worst_momentum,
                             float(np.max(np.abs(mom.sum(axis=0) - (m[:, None] * v).sum(axis=0)))) / scale)
        bad_order += int(np.any(np.diff(mass) > 0.0))
        counts = np.bincount(frag, minlength=len(cat))
        masses = np.bincount(frag, weights=m, minlength=len(cat))
        bad_index += int(len(counts) != len(cat) or np.any(counts != count)
                         or np.any(np.abs(masses - mass) > 1e-12 * mass))
        multi = counts[frag] >= 2
        bad_members += int(np.any(D[multi] >= THRESHOLD))
        if abs(t - 2e-6) < 1e-9:
            failed = (body == 0) & (D >= 1.0)
            check(failed.sum() > 0 and y[failed].mean() > 0.0,
                  f"t = 2 us: {failed.sum()} failed target particles, mean height "
                  f"{y[failed].mean() * 1e3 if failed.any() else 0:.2f} mm above the centre (impact side)")
        last = (t, mass, count)
    check(worst_mass < 1e-12, f"fragment masses sum to the particles' mass (worst {worst_mass:.1e})")
    check(worst_momentum < 1e-12, f"fragment momenta sum to the particles' (worst {worst_momentum:.1e})")
    check(bad_index == 0, f"each particle's `fragment` is its row in the catalogue ({bad_index} snapshots off)")
    check(bad_order == 0, "catalogues ordered by mass, largest first")
    check(bad_members == 0, "no failed particle inside a fragment of two or more")
    t, mass, count = last
    big = int(np.sum(count >= 10))
    check(mass[0] / mass.sum() < 0.5 and big >= 5,
          f"t = {t * 1e6:.3g} us: largest fragment {mass[0] / mass.sum() * 100:.1f}% of the mass, "
          f"{big} fragments of 10 particles or more, {len(mass)} in all")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
