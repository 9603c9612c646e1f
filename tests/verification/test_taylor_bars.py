#!/usr/bin/python3
"""Taylor anvil tests against their published references (decks/taylor_bar_*.toml; issue 21):
the final length and impact-face diameter measured by tools/taylor, the deformed profile against
the published one where the deck carries it, and no particle below the rigid wall in any
snapshot. Runs on 2 ranks.

Fast (default), at half the shipped resolution (about 5 particles across the radius, where the
smoothing scale, 1.5 spacings, is a third of the radius):
- (long only since 2026-12-02, to keep CI under 15 minutes: the 4340 bar below guards the same
  Johnson-Cook bar against the wall in 3D, with a profile besides) 42CrMo4 steel (Pantale et
  al., DynELA and Abaqus, the same Johnson-Cook model: 26.55 mm, 11.19 mm), 3.8k particles at
  half resolution: length and face within 4%. Measured -2.7% and -3.0%; -2.0% and -0.7% at 7
  across (decks/topics/taylor-bars.md). Before the wall's hold replaced its images' viscosity
  the face came out -7.3% there, and 16% narrow with the plain viscosity.
- 4340 steel (Johnson & Cook's 1983 test, 22.48 mm, 11.1 mm, and its profile), 2.4k particles:
  length within 3%, face within 4%, profile RMS within 3% of the radius. Measured -0.95%, -3.4%
  and 1.9%; the rz bar gives -3.7% from 9.6 to 38 rings across the radius (converged), so the
  remaining face error is the model's against the test. Before the hold: -0.7%, -7.6%, 3.5%.

With `long`: the shipped resolutions (10 across the radius; ~17 min and ~10 min on 2 cores):
42CrMo4 and 4340 within the issue's 2% (length) and 4% (face), 4340's profile RMS within 3%
(measured: 42CrMo4 -1.6%, +0.3%; 4340 -0.74%, -3.97%, 1.9%). The OFHC copper bar with Johnson-Cook
(taylor_bar_3d) is measured, not asserted: its length stays about 5% long at every resolution
(decks/README.md). With Zerilli-Armstrong:
- long (fast until 2026-12-02; the model itself is held to its closed forms in
  tests/unit/materials/test_strength.cpp, and the fast suite's 4340 bar guards the Taylor
  impact), taylor_bar_za_rz (axisymmetric, 15 rings across the radius, 1.5k particles, 44 s on 1 core):
  length within 4%, face within 4%, profile RMS within 4%. Measured +3.3%, -2.6%, 2.6% (at 1.5x
  the resolution +3.7%, -2.2%, 2.55%). The rz bar ends 1-2% longer than the 3D one for both
  models. The same deck with Johnson-Cook (taylor_bar_rz) gives +6.4%, +5.0% and 7.5%: the
  profile bound is the one its separable rate term fails.
- long, taylor_bar_za_3d at resolution 0.7 (10.5 across, 23k particles, ~13 min on 2 cores): length
  within 3%, face within 5%, profile RMS within 4%. Measured +1.9%, -4.35%, 3.2% (at 7.5 across
  +1.3%, -5.5%, 3.5%): at two thirds of the shipped resolution the face still converges toward
  the rz runs' -2.6% and -2.2%, and 5% is what this resolution earns. The shipped 15 across
  (71.6k particles, 1 h 43 min on 2 ranks) gives +2.7%, -2.1%, 2.3%: the length grows toward the
  rz bar's +3.3-3.7%, so the issue's 2% on the length is not met there with either model.

A user's variation (issue 67): the 42CrMo4 bar with `kernel = "wendland_c2"`, Balsara's switch,
8 particles across the radius (0.4 mm) and a run to 100 us. The face by the particles within two
spacings of the wall: the 99th percentile of their radii within 5% of the reference face, the
outermost within 8% (the issue's bounds). Balsara's switch takes the viscosity out of isochoric
flow, close pairs included, and the mushroom's rim spread: in 3D, against the deck's 11.19 mm,
the outermost +6.4% and the 99th percentile +5.7% before a pair closer than the mean spacing
took its viscosity back (solvers/SphPairTerms.hpp, balsaraPair); with it +5.4% and +4.4% (long:
16.8k particles, ~14 min on 2 ranks). Fast: the same bar in rz (the deck's cylinder as r, z), 8
rings, ~20 s: +2.0% and +1.2% (+2.5% and +1.8% before).

usage: test_taylor_bars.py SPALL SOURCE_DIR [long]
"""
import importlib.machinery
import importlib.util
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
LONG = len(sys.argv) > 3 and sys.argv[3] == "long"

loader = importlib.machinery.SourceFileLoader("taylor", str(SRC / "tools" / "taylor"))
spec = importlib.util.spec_from_loader("taylor", loader)
taylor = importlib.util.module_from_spec(spec)
loader.exec_module(taylor)

# deck, resolution, length tolerance, diameter tolerance, profile RMS tolerance (None: no profile)
CASES = [("taylor_bar_steel_3d.toml", 1.0, 0.02, 0.04, None),
         ("taylor_bar_4340_3d.toml", 1.0, 0.02, 0.04, 0.03),
         ("taylor_bar_za_3d.toml", 0.7, 0.03, 0.05, 0.04),
         ("taylor_bar_za_rz.toml", 1.0, 0.04, 0.04, 0.04)] if LONG else \
        [("taylor_bar_4340_3d.toml", 0.5, 0.03, 0.04, 0.03)]

# A user's variation of the 42CrMo4 deck (docstring): 3D in long, rz in the fast suite.
VARIATION = ["solver.kernel=wendland_c2", "solver.artificial_viscosity.balsara=true",
             "body.bar.spacing=4.0e-4", "run.end_time=1.0e-4"]
FACE_P99, FACE_MAX = 0.05, 0.08  # the bounds: the rim, and its outermost particle


def rz_deck(tmp):
    """decks/taylor_bar_steel_3d.toml as an rz bar: the cylinder as [0, R] x [0, L]."""
    s = (SRC / "decks" / "taylor_bar_steel_3d.toml").read_text()
    for a, b in (("dimension = 3", 'dimension = 2\ngeometry = "rz"'),
                 ('shape = { type = "cylinder", base = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], '
                  'radius = 3.2e-3, length = 32.4e-3 }',
                  'shape = { type = "box", min = [0.0, 0.0], max = [3.2e-3, 32.4e-3] }'),
                 ("velocity = [0.0, 0.0, -287.0]", "velocity = [0.0, -287.0]"),
                 ("point = [0.0, 0.0, 0.0]", "point = [0.0, 0.0]"),
                 ("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 1.0]")):
        assert a in s, a
        s = s.replace(a, b)
    path = Path(tmp) / "taylor_bar_steel_rz.toml"
    path.write_text(s)
    return path


def face_radii(out):
    """Distances from the axis of the particles within two spacings of the wall at the end, and
    the reference face diameter (tools/taylor's reading of the deck)."""
    bar = taylor.setup(Path(out) / "deck.toml")
    _, z, r, _ = taylor.heights_and_radii(taylor.snapshot_files(out)[-1], bar)
    return r[z < 2.0 * bar["spacing"]], bar["reference"][1]


failures = []
with tempfile.TemporaryDirectory() as tmp:
    variation = (SRC / "decks" / "taylor_bar_steel_3d.toml") if LONG else rz_deck(tmp)
    out = Path(tmp) / "variation"
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", SPALL, "run",
           str(variation), "--output", str(out), "--quiet"]
    p = subprocess.run(cmd + [a for k in VARIATION for a in ("--set", k)], capture_output=True,
                       text=True, stdin=subprocess.DEVNULL)
    if p.returncode != 0:
        failures.append(f"variation {variation.name}: exit {p.returncode}\n{p.stderr[-2000:]}")
    else:
        r, D0 = face_radii(out)
        d99, dmax = 2.0 * np.percentile(r, 99) / D0 - 1.0, 2.0 * r.max() / D0 - 1.0
        print(f"variation {variation.name} ({', '.join(VARIATION)}): face by the 99th percentile "
              f"{d99 * 100:+.2f}% (within {FACE_P99 * 100:g}%), by the outermost particle "
              f"{dmax * 100:+.2f}% (within {FACE_MAX * 100:g}%) of {D0 * 1e3:.2f} mm")
        if abs(d99) > FACE_P99 or abs(dmax) > FACE_MAX:
            failures.append(f"variation {variation.name}: face {d99 * 100:+.2f}% (99th percentile), "
                            f"{dmax * 100:+.2f}% (outermost)")

    for deck, resolution, tol_length, tol_diameter, tol_profile in CASES:
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
        if tol_profile is not None:
            print(f"  profile against the test: RMS {m['profile_rms'] * 100:.2f}%, largest "
                  f"{m['profile_max'] * 100:.2f}% of the radius")
            if m["profile_rms"] > tol_profile:
                failures.append(f"{deck}: profile RMS {m['profile_rms'] * 100:.2f}% beyond {tol_profile * 100:g}%")
        for row in m["rows"]:
            if row["lowest"] < 0.0:
                failures.append(f"{deck}: a particle {-row['lowest'] * 1e6:.1f} um below the wall at "
                                f"t = {row['time'] * 1e6:.1f} us")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
