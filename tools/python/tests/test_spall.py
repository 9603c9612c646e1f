#!/usr/bin/python3
"""The Python package spall (tools/python/spall) on runs of the binary: a segmented rod into
steel (rz, a [[jet]] whose segments are bodies) and the stretching rod (plane, ASPH, a recorded
particle). Checked against what the run itself wrote by other routes, so a wrong reader fails:
- names: every particle's material name is the one the deck gives its body (a jet's segments
  take the jet's material), and the segments present are named as the deck's jet rows;
- units: every field carries one, "kg" for an rz mass (a full ring), "kg/m" in plane strain;
- conservation: the particles' summed mass and momentum equal history.csv's at the snapshot's
  time (to 1e-12 relative: the same sums, only their order differs);
- tensors: the snapshot's deformation gradient of the recorded particle equals the F-table row
  the run recorded at that step (particles/particle_0.ftable, F11 F12 ... row-major, %.17g:
  exact); that particle shears, so a transposed reading fails (F12 - F21 checked non-zero);
- series: a field over the snapshots for chosen ids equals the row-by-row lookups;
- tables: probes.csv's string and number columns, filtering by value; errors name the file.

- install: `cmake --install BUILD_DIR --component python` puts a package /usr/bin/python3
  imports (given BUILD_DIR).

usage: test_spall.py SPALL SOURCE_DIR [BUILD_DIR]
"""
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
sys.path.insert(0, str(SRC / "tools" / "python"))
import spall  # noqa: E402

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def run(deck, out, *sets):
    cmd = [SPALL, "run", str(deck if isinstance(deck, Path) else SRC / "decks" / deck),
           "--output", str(out)]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, stdin=subprocess.DEVNULL)
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stderr[-3000:]}")


def rz_jet(tmp):
    out = tmp / "segmented"
    # 0.3 of the deck's resolution; 60 steps: segment 1 is in from t = 0.
    run("rod_segmented_into_steel_rz.toml", out, "run.resolution=0.3", "run.max_steps=60",
        "output.every_steps=30", "output.history_every_steps=30")
    r = spall.Run(out)
    check(len(r) == 3, f"{len(r)} snapshots listed (steps 0, 30, 60)")
    s = r.snapshot(-1)
    deck = r.deck
    check(s.geometry == "rz" and s.axes == "r z" and s.dimension == 2,
          f"geometry {s.geometry!r}, axes {s.axes!r}")
    check(s.materials == [m["name"] for m in deck["material"]],
          f"material names {s.materials} are the deck's, in its order")
    bodies = {b["name"]: b["material"] for b in deck["body"]}
    jet = deck["jet"][0]
    for row in jet["segments"]:
        bodies[f"{jet['name']}_segment{int(row[0])}"] = jet["material"]
    check(set(s.bodies) == set(bodies), f"{len(s.bodies)} body names: the deck's bodies and "
          f"its jet's {len(jet['segments'])} segments")
    want = np.array([bodies[b] for b in s.body_names], dtype=object)
    check(np.all(s.material_names == want),
          "every particle's material name is its body's material in the deck")
    present = sorted(set(s.body_names))
    check(f"{jet['name']}_segment1" in present and "billet" in present or len(present) >= 2,
          f"bodies present at step {s.step}: {present}")
    check(all(s.unit(f) for f in s.fields), "every field has a unit: " +
          ", ".join(f for f in s.fields if not s.unit(f)))
    check(s.units["mass"] == "kg" and s.units["stress"] == "Pa" and s.units["id"] == "1",
          f"rz units: mass {s.units['mass']}, stress {s.units['stress']}")
    h = r.history
    k = int(np.argmin(np.abs(h["time"] - s.time)))
    mass, pz = s["mass"].sum(), (s["mass"] * s["velocity"][:, 1]).sum()
    check(h["time"][k] == s.time and abs(mass / h["mass"][k] - 1) < 1e-12 and
          abs(pz / h["momentum_y"][k] - 1) < 1e-12,
          f"mass {mass:.15g} kg and z momentum {pz:.12g} are history.csv's at t = {s.time:.4g} s")
    check(abs(r.times[-1] - s.time) == 0 and r.at(0.0).step == 0, "times and at()")
    ids = s.ids[[0, len(s) // 2, len(s) - 1]]
    times, v = r.series("velocity", ids)
    direct = np.array([spall.Snapshot(p)["velocity"][spall.Snapshot(p).rows(ids)]
                       if set(ids.tolist()) <= set(spall.Snapshot(p).ids.tolist())
                       else np.full((3, 2), np.nan) for p in r.snapshots])
    check(np.array_equal(times, r.times) and np.array_equal(v, direct, equal_nan=True),
          "series('velocity', ids) is the snapshots' rows of those ids")
    pen = r.penetration
    check(pen is not None and "depth" in pen and len(pen) > 0, f"penetration.csv: {pen}")
    check(r.summary and r.summary["status"] == "finished" and r.summary["steps"] == 60,
          "summary.json as a dict")
    try:
        s["no_such_field"]
        check(False, "a missing field raises")
    except KeyError as e:
        check("no_such_field" in str(e) and "density" in str(e), f"a missing field: {e}")


def plane_tensors(tmp):
    out = tmp / "stretching"
    deck = tmp / "stretching_rod_probed.toml"
    deck.write_text((SRC / "decks" / "stretching_rod_2d.toml").read_text() +
                    '\n[[probe]]\nname = "tip"\nposition = [0.0, 0.0]\n'
                    'fields = ["density", "pressure"]\n')
    run(deck, out, "run.max_steps=120", "output.every_steps=60",
        'output.record_particles=[0]',
        'output.fields=["velocity", "mass", "material", "body", "deformation_gradient", '
        '"stress"]')
    r = spall.Run(out)
    s = r.snapshot(-1)
    check(s.geometry == "plane" and s.units["mass"] == "kg/m", f"plane: mass in {s.units['mass']}")
    rows = [l.split() for l in (out / "particles" / "particle_0.ftable").read_text().splitlines()
            if l.strip() and not l.startswith("#")]
    at = {float(x[0]): np.array([float(v) for v in x[1:10]]).reshape(3, 3) for x in rows}
    F = s["deformation_gradient"][s.rows([0])[0]]
    check(s.time in at and np.array_equal(F, at[s.time]),
          f"particle 0's F at t = {s.time:.4g} s is its recorded row:\n{F}")
    check(abs(F[0, 1] - F[1, 0]) > 1e-6, f"and it shears: F12 - F21 = {F[0, 1] - F[1, 0]:.3g}")
    sig = s["stress"]
    check(sig.shape == (len(s), 2, 2) and np.allclose(sig[:, 0, 1], sig[:, 1, 0], rtol=0,
                                                     atol=1e-6 * np.abs(sig).max()),
          "stress [N, 2, 2], symmetric")
    p = r.probes
    check(p is not None and p["probe"].dtype.kind == "U" and p["value"].dtype.kind == "f",
          f"probes.csv: {p}")
    tip = p.where(probe="tip", field="density")
    check(len(tip) == len(r.history) and np.all(tip["value"] > 0),
          f"{len(tip)} rows of the tip's density, one per history row")


def errors(tmp):
    for bad in (tmp / "nowhere", tmp):
        try:
            spall.Run(bad)
            check(False, f"Run({bad}) raises")
        except FileNotFoundError as e:
            check(str(bad) in str(e), f"Run of a non-run: {e}")
    (tmp / "ragged.csv").write_text("a,b\n1,2\n3\n")
    try:
        spall.read_csv(tmp / "ragged.csv")
        check(False, "a ragged CSV raises")
    except ValueError as e:
        check("ragged.csv:3" in str(e), f"a ragged CSV: {e}")


def install(tmp, build):
    prefix = tmp / "prefix"
    p = subprocess.run(["cmake", "--install", build, "--prefix", prefix, "--component", "python"],
                       capture_output=True, text=True)
    found = sorted(prefix.glob("lib/python3*/dist-packages/spall/__init__.py"))
    check(p.returncode == 0 and len(found) == 1,
          f"cmake --install --component python: {found or p.stderr[-500:]}")
    if found:
        q = subprocess.run(["/usr/bin/python3", "-c", "import spall; print(spall.Run.__doc__)"],
                           capture_output=True, text=True,
                           env=dict(ENV, PYTHONPATH=str(found[0].parent.parent)),
                           cwd=tmp)
        check(q.returncode == 0 and "snapshot" in q.stdout, "the installed package imports")


with tempfile.TemporaryDirectory() as d:
    tmp = Path(d)
    if len(sys.argv) > 3:
        install(tmp, sys.argv[3])
    rz_jet(tmp)
    plane_tensors(tmp)
    errors(tmp)
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
