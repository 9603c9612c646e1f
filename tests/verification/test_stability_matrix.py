#!/usr/bin/python3
"""The stability matrix's fast subset (tools/stress; issue 19): projectile-into-plate impacts at
1, 6 and 10 km/s for density ratios 1:1, 1:3.2 and 1:7.1, hydro and von Mises strength, and the
train of copper jet segments at 6-8 km/s, in 2D SPH at the coarse resolution, and the hydro
projectile cells in 2D ASPH at the coarse resolution (those a regression had taken: with the
ellipse's shape taken from the Voronoi cell at once, al_al at 6 km/s, cu_al at 6 and 10 and w_al
at 1 failed; solvers/IdealH.hpp). With `long` as the third argument: every cell (2D and 3D, SPH
and ASPH, strength on and off, coarse and fine). MPM's cells, 2D coarse, hydro and strength, as
an impact wants them run: a velocity field per body (contact "frictionless") and Uintah's shock
viscosity (C_L 0.2, C_Q 2.0; decks/topics/mpm.md).

Every cell must finish, and:
- energy error |E(t) - E(0)| / E(0) below 1e-3: the leapfrog and the conservative pair terms
  keep it near 1e-5 in these runs (measured 1e-6 to 2e-5 for SPH, 5e-6 to 9e-5 for ASPH); a
  pairing instability pumps energy without bound (1e11 measured before the fix), so the bound
  separates the two by decades;
- every material's max density below 1.2 times its density in the impact's Hugoniot state
  (tools/stress's rho/rho_H: the planar impact at V, rho_H = rho0 Us/(Us - up); the sphere's later,
  oblique contact compresses less): SPH and ASPH measured 0.75-1.007 in the fast subset, MPM
  1.02-1.17; interpenetrating particles reach 10 to 1e10, and MPM with one velocity field and no
  shock viscosity 3.2 (W on Al at 10 km/s: the tungsten's aluminium neighbors at 6.3 times their
  reference, a shock that rings with nothing to damp it at the nodes the two bodies share). The
  bound is issue 65's, 20% above the state a numerical shock should not overshoot by more than
  its ringing;
- MPM's energy error below 0.2: its contact stops the fields' approach at the nodes where they
  first meet, an inelastic collision whose loss is not booked as heat (decks/topics/mpm.md;
  measured 3.6-13.5%, the same-material pair the most); a runaway grows it without bound;
- smallest dt over the first above 0.05: the shocked sound speed and particle speed lower the
  step 3-8x (measured 0.12-0.8 for SPH, 0.085-0.38 for ASPH); a collapse takes it to 1e-10.

usage: test_stability_matrix.py SPALL SOURCE_DIR [long]

With `long`: 2D SPH and ASPH at both resolutions with and without strength, and 3D SPH at 1, 6
and 10 km/s (~1 h on 2 cores; 3D ASPH takes minutes a cell and is left to `tools/stress --full`).
ASPH at the fine resolution is not yet stable in every impact: a debris particle in deep tension
behind the plate can pair with a neighbor (3 to 13 times the reference density beside neighbors at
0.4, the energy still within 1e-4) or fly apart (cu_al at 6 km/s with strength went non-finite at
2.5 us in one build; measured 17 or 18 of 18 finished, which depends on the last bits). A fine
ASPH cell out of its reach must end in exit 1 with the diagnostic and a checkpoint of the last
good state (issue 19), and its density is reported, not bounded; its energy bound is 1e-2.
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
LONG = len(sys.argv) > 3 and sys.argv[3] == "long"
if LONG:
    runs = [["--methods", "sph,asph", "--resolutions", "coarse,fine", "--strength", "off,on",
             "--pairs", "al_al,cu_al,w_al,jet"],
            ["--dims", "3", "--speeds", "1,6,10", "--strength", "off,on"]]
else:
    runs = [["--speeds", "1,6,10", "--pairs", "al_al,cu_al,w_al,jet", "--strength", "off,on"],
            ["--methods", "asph", "--speeds", "1,6,10", "--pairs", "al_al,cu_al,w_al"]]
runs.append(["--methods", "mpm", "--speeds", "1,6,10", "--pairs", "al_al,cu_al,w_al,jet",
             "--strength", "off,on", "--set", "solver.contact=frictionless",
             "--set", "solver.mpm.viscosity={linear=0.2, quadratic=2.0}"])
rows = []
with tempfile.TemporaryDirectory() as tmp:
    for k, args in enumerate(runs):
        table = Path(tmp) / f"matrix{k}.json"
        subprocess.run(["/usr/bin/python3", str(SRC / "tools/stress"), "--spall", SPALL, "--json",
                        str(table), "--timeout", "3600", *args], text=True)
        rows += json.loads(table.read_text())
failures = []
for row in rows:
    name = row["name"]
    # ASPH beyond its reach: the fine resolution and 3D (see above).
    lenient = row["method"] == "asph" and (row["resolution"] == "fine" or row["dim"] == 3)
    if lenient and row["exit"] != 0:
        if row["exit"] != 1 or "last good state" not in row["detail"]:
            failures.append(f"{name}: out of reach but without the diagnostic: {row['message']}")
        else:
            print(f"out of reach (ASPH, failed with the diagnostic): {name}")
        continue
    if row["exit"] != 0:
        failures.append(f"{name}: did not finish: {row['message']}")
        continue
    bound = 0.2 if row["method"] == "mpm" else 1e-2 if lenient else 1e-3
    if not row["energy_error"] < bound:
        failures.append(f"{name}: energy error {row['energy_error']} (bound {bound})")
    if lenient:
        print(f"{name}: max density {row['compression']} x reference, {row['over_hugoniot']} x "
              "the Hugoniot state's (reported)")
    elif row["over_hugoniot"] is None or not row["over_hugoniot"] < 1.2:
        failures.append(f"{name}: max density {row['over_hugoniot']} x the Hugoniot state's "
                        f"({row['compression']} x reference; bound 1.2)")
    if not row["dt_ratio"] > 0.05:
        failures.append(f"{name}: dt fell to {row['dt_ratio']} of the first")
print(f"{len(rows)} cells, {len(failures)} failure(s)")
for f in failures:
    print("FAIL", f)
sys.exit(1 if failures or not rows else 0)
