#!/usr/bin/python3
"""Bodies that join a run at insert_time, and [[jet]] files turned into such bodies.

A copper jet of three segments (a jet file, rz) into a steel block, segments at t = 0, 1 and 2 us:
1. history.csv: the particle count rises by each segment's count at the row of its insert time
   (the step before is shortened to end on it), and not before.
2. The snapshot at 1 us (written after the insertion): segment 2's particles, ids fixed at t = 0
   (after the block's and segment 1's), all at the segment's speed, between the entry and one
   segment length behind it.
3. The same run on 1 and 5 ranks: the final particles identical bit for bit; stopped on 2 ranks
   at a step while segment 3 waits and restarted on 3: identical too.
4. Conservation with bodies joining: the closing mass, z-momentum and energy errors are judged
   against what the run held plus what joined (mass and momentum to 1e-12, energy 1e-4: the time
   integration's; measured 1e-15, 6e-16 and 9e-6).
5. A plain [[body]] with insert_time (plane strain): the same count and id checks.

usage: test_insert_time.py SPALL SOURCE_DIR
"""
import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
failures = []

JET_CSV = """segment,radius,length,velocity,insert_time
1,1.0e-3,4.0e-3,6000.0,0.0
2,1.0e-3,4.0e-3,5500.0,1.0e-6
# a comment line
3,0.9e-3,4.0e-3,5000.0,2.0e-6
"""

DECK = """
[run]
title = "jet of three segments into steel"
dimension = 2
geometry = "rz"
end_time = 3.0e-6
[[material]]
name = "copper"
density = 8930.0
eos = { type = "mie_gruneisen", c0 = 3940.0, s = 1.49, gamma0 = 2.02 }
[[material]]
name = "steel"
density = 7850.0
eos = { type = "mie_gruneisen", c0 = 4569.0, s = 1.49, gamma0 = 2.17 }
[[body]]
name = "block"
material = "steel"
shape = { type = "box", min = [0.0, -20.0e-3], max = [10.0e-3, -2.0e-3] }
spacing = 4.0e-4
[[jet]]
file = "jets/three.csv"
material = "copper"
axis = [0.0, -1.0]
entry = [0.0, 0.0]
spacing = 2.5e-4
[output]
directory = "out/jet"
every = 1.0e-6
"""


def check(ok, message):
    print(("ok   " if ok else "FAIL ") + message)
    if not ok:
        failures.append(message)


def run(deck, out, *sets, ranks=1, restart=None):
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), SPALL, "run",
           str(deck), "--output", str(out), "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    if restart:
        cmd += ["--restart", restart]
    p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    if p.returncode != 0:
        check(False, f"{out.name}: exit {p.returncode}\n{p.stderr[-2000:]}")
        return False
    return True


def snapshot(path):
    g = h5py.File(path, "r")["particles"]
    order = np.argsort(np.array(g["id"]))
    return {k: np.array(g[k])[order] for k in g.keys()}


def final(out):
    return snapshot(sorted((out / "snapshots").glob("snap_*.h5"))[-1])


def counts_at_times(out, joins, label):
    """joins: [(time, count)] of the bodies joining after t = 0."""
    rows = list(csv.DictReader(open(out / "history.csv")))
    t = np.array([float(r["time"]) for r in rows])
    n = np.array([int(r["particles"]) for r in rows])
    ok = True
    for time, count in joins:
        k = int(np.searchsorted(t, time * (1 - 1e-12)))
        ok &= k < len(t) and abs(t[k] - time) <= 1e-12 * time and n[k] - n[k - 1] == count
    steps_up = int(np.count_nonzero(np.diff(n)))
    check(ok and steps_up == len(joins),
          f"{label}: the count rises by each body's particles at the row of its insert time "
          f"({', '.join(f'{c} at {tt:g} s' for tt, c in joins)}), nowhere else")


def jet(tmp):
    (tmp / "jets").mkdir()
    (tmp / "jets/three.csv").write_text(JET_CSV)
    deck = tmp / "jet.toml"
    deck.write_text(DECK)
    one, five, half = tmp / "one", tmp / "five", tmp / "half"
    if not run(deck, one):
        return
    # Segment counts: rz boxes r in [0, R], 4 mm long at 0.25 mm: 16 layers x R/0.25 mm rings.
    n1, n2, n3 = 16 * 4, 16 * 4, 16 * 4  # R = 1, 1, 0.9 mm: 4, 4 and round(3.6) = 4 rings
    counts_at_times(one, [(1e-6, n2), (2e-6, n3)], "jet (rz)")
    s = snapshot(one / "snapshots/snap_000001.h5")
    block = len(s["id"]) - n1 - n2
    seg2 = (s["id"] >= block + n1) & (s["id"] < block + n1 + n2)
    check(seg2.sum() == n2 and np.all(s["body"][seg2] == 2),
          f"jet: at 1 us segment 2's {n2} particles carry ids {block + n1}.. (fixed at t = 0)")
    z = s["position"][seg2, 1]
    # Flying along -z: its front is its lowest layer, half a spacing behind the entry (z = 0).
    check(np.all(s["velocity"][seg2, 1] == -5500.0) and np.all(s["velocity"][seg2, 0] == 0.0)
          and abs(z.min() - 1.25e-4) < 1e-12 and abs(z.max() - (4.0e-3 - 1.25e-4)) < 1e-12,
          "jet: segment 2 enters at its speed, its front at the entry, 4 mm long behind it")
    c = json.loads((one / "summary.json").read_text())["conservation"]
    check(c["mass_relative"] < 1e-12 and c["momentum_relative"] < 1e-12 and
          c["energy_relative"] < 1e-4,
          f"jet: conservation with the segments' joins counted (mass {c['mass_relative']:.1e}, "
          f"momentum {c['momentum_relative']:.1e}, energy {c['energy_relative']:.1e})")

    if not run(deck, five, ranks=5):
        return
    a, b = final(one), final(five)
    differ = [k for k in a if not np.array_equal(a[k], b[k])]
    check(not differ, "jet: 1 and 5 ranks, final particles bit for bit" +
          (f" (differ: {differ})" if differ else ""))
    rows = list(csv.DictReader(open(one / "history.csv")))
    waiting_step = next(int(r["step"]) for r in rows if float(r["time"]) > 1.5e-6)
    if not (run(deck, half, f"run.max_steps={waiting_step}", ranks=2) and
            run(deck, half, ranks=3, restart="latest")):
        return
    c = final(half)
    differ = [k for k in a if not np.array_equal(a[k], c[k])]
    check(not differ, f"jet: stopped at step {waiting_step} (segment 3 waiting) on 2 ranks, "
          "restarted on 3: final particles bit for bit" + (f" (differ: {differ})" if differ else ""))


PLAIN = """
[run]
title = "a plate that joins later"
dimension = 2
end_time = 1.0e-6
[[material]]
name = "m"
density = 2700.0
eos = { type = "mie_gruneisen", c0 = 5350.0, s = 1.34, gamma0 = 2.0 }
[[body]]
name = "late"
material = "m"
shape = { type = "box", min = [0.0, 2.0e-3], max = [2.0e-3, 3.0e-3] }
spacing = 2.5e-4
velocity = [0.0, -200.0]
insert_time = 0.35e-6
[[body]]
name = "base"
material = "m"
shape = { type = "box", min = [0.0, 0.0], max = [4.0e-3, 1.0e-3] }
spacing = 2.5e-4
[output]
directory = "out/plain"
every = 0.5e-6
"""


def plain(tmp):
    deck = tmp / "plain.toml"
    deck.write_text(PLAIN)
    out = tmp / "plain"
    if not run(deck, out, ranks=2):
        return
    counts_at_times(out, [(0.35e-6, 32)], "plane strain body")
    s = final(out)
    late = s["body"] == 0
    check(late.sum() == 32 and np.array_equal(np.sort(s["id"][late]), np.arange(32)),
          "plane strain body: listed first, it keeps ids 0..31 though it joined last")


with tempfile.TemporaryDirectory() as d:
    jet(Path(d))
    plain(Path(d))

print(f"{len(failures)} failure(s)" if failures else "all insert-time checks passed")
sys.exit(1 if failures else 0)
