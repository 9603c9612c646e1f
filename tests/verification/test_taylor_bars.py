#!/usr/bin/python3
"""Taylor anvil tests against their published references (decks/taylor_bar_*.toml; issue 21):
the final length and impact-face diameter measured by tools/taylor, and no particle below the
rigid wall in any snapshot.

Fast (default): the 42CrMo4 steel bar (Pantale et al., DynELA and Abaqus: 26.55 mm, 11.19 mm) at
half the shipped resolution, 5 particles across the radius (~3.9k particles), on 2 ranks.
Tolerances: length within 4%, face diameter within 8%. At this resolution the smoothing scale
(1.5 spacings) is a third of the bar's radius, and the run measures -2.4% and -7.3%; the
convergence study (decks/README.md, "Taylor bars") has both errors shrinking with resolution
(-1.5% and -1.6% at the shipped one). The bound still separates the viscosity the defaults use
from the plain one, whose face comes out 16% narrow here.

With `long`: the shipped resolution (10 across the radius, 30.8k particles, ~17 min on 2
cores): length within 2% and face diameter within 4% (the issue's bounds).

usage: test_taylor_bars.py SPALL SOURCE_DIR [long]
"""
import importlib.machinery
import importlib.util
import subprocess
import sys
import tempfile
from pathlib import Path

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
LONG = len(sys.argv) > 3 and sys.argv[3] == "long"

loader = importlib.machinery.SourceFileLoader("taylor", str(SRC / "tools" / "taylor"))
spec = importlib.util.spec_from_loader("taylor", loader)
taylor = importlib.util.module_from_spec(spec)
loader.exec_module(taylor)

# deck, resolution, length tolerance, diameter tolerance
CASES = [("taylor_bar_steel_3d.toml", 1.0, 0.02, 0.04)] if LONG else \
        [("taylor_bar_steel_3d.toml", 0.5, 0.04, 0.08)]

failures = []
with tempfile.TemporaryDirectory() as tmp:
    for deck, resolution, tol_length, tol_diameter in CASES:
        out = Path(tmp) / deck
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", SPALL, "run",
               str(SRC / "decks" / deck), "--output", str(out), "--quiet",
               "--set", f"run.resolution={resolution:g}"]
        p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
        if p.returncode != 0:
            failures.append(f"{deck}: exit {p.returncode}\n{p.stderr[-2000:]}")
            continue
        m = taylor.measure(out)
        print(f"{deck} at resolution {resolution:g}: length {m['length'] * 1e3:.3f} mm "
              f"({m['length_error'] * 100:+.2f}%), face {m['diameter'] * 1e3:.3f} mm "
              f"({m['diameter_error'] * 100:+.2f}%), lowest particle {m['lowest'] / m['spacing']:.3f} "
              f"spacings above the wall")
        if abs(m["length_error"]) > tol_length:
            failures.append(f"{deck}: length error {m['length_error'] * 100:+.2f}% beyond {tol_length * 100:g}%")
        if abs(m["diameter_error"]) > tol_diameter:
            failures.append(f"{deck}: face diameter error {m['diameter_error'] * 100:+.2f}% beyond "
                            f"{tol_diameter * 100:g}%")
        for row in m["rows"]:
            if row["lowest"] < 0.0:
                failures.append(f"{deck}: a particle {-row['lowest'] * 1e6:.1f} um below the wall at "
                                f"t = {row['time'] * 1e6:.1f} us")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
