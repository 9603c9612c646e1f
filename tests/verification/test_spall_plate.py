#!/usr/bin/python3
"""Plate-impact spall against the wave diagram (decks/spall_plate_1d.toml; issue 15).

A flyer of thickness d_f hits a target of thickness d_t of the same material below its Hugoniot
elastic limit: the release from the flyer's rear face meets the tension reflected from the
target's free face at x0 = d_t - d_f (Lagrangian), where the tension first reaches its full
amplitude. The damage there: the damage-weighted centroid of the target, in initial positions,
at the first output (every 10 ns, a twentieth of the 0.2 us the pulse takes to cross a flyer)
in which a target particle has failed, must lie within one smoothing length (1.5 spacings) of
x0. The shipped deck, a thinner flyer (x0 = 4.5 mm) and a faster one (80 m/s, just above the
HEL): measured offsets +6.5, -8.6 and -1.1 um against h = 18.75 um. (At twice the spacing the
offsets grow to 40-58 um, 1.1-1.5 h: the centroid converges, and the deck ships at the spacing
where it is within h.) Also: the scab (the target beyond the failed band) flies off at the
flyer's speed within 5% (it carries the trapped front half of the pulse; measured 2.2-2.6% slow).

usage: test_spall_plate.py SPALL SOURCE_DIR
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
DECK = SRC / "decks" / "spall_plate_1d.toml"
SPACING = 1.25e-5
H = 1.5 * SPACING  # nodes_per_h

# --set overrides, d_t - d_f (m), flyer speed (m/s)
CASES = [([], 0.004, 60.0),
         (["body.flyer.shape.min=[-0.0015]"], 0.0045, 60.0),
         (["body.flyer.velocity=[80.0]"], 0.004, 80.0)]

failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def load(path):
    with h5py.File(path, "r") as f:
        g = f["particles"]
        return {k: g[k][()] for k in ("id", "position", "damage", "body", "velocity")}, \
            float(f.attrs["time"])


with tempfile.TemporaryDirectory() as tmp:
    for sets, x_spall, speed in CASES:
        out = Path(tmp) / f"run{len(failures)}_{len(sets)}_{speed:g}"
        cmd = [SPALL, "run", str(DECK), "--output", str(out), "--quiet",
               "--set", "output.every=1e-8", "--set", "run.end_time=3e-6"]
        for s in sets:
            cmd += ["--set", s]
        p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
        label = ", ".join(sets) or "shipped deck"
        if p.returncode != 0:
            check(False, f"{label}: exit {p.returncode}\n{p.stderr[-2000:]}")
            continue
        snaps = sorted((out / "snapshots").glob("snap_*.h5"))
        first, _ = load(snaps[0])
        x0 = dict(zip(first["id"], first["position"][:, 0]))
        centroid, when = None, None
        for snap in snaps:
            a, t = load(snap)
            target = a["body"] == 1
            D = np.where(target, a["damage"], 0.0)
            if D.max() >= 1.0:
                X0 = np.array([x0[i] for i in a["id"]])
                centroid, when = float(np.sum(D * X0) / np.sum(D)), t
                break
        if centroid is None:
            check(False, f"{label}: the target never failed")
            continue
        check(abs(centroid - x_spall) <= H,
              f"{label}: first failure at t = {when * 1e6:.2f} us, damage centroid x0 = "
              f"{centroid * 1e3:.4f} mm, {(centroid - x_spall) * 1e6:+.1f} um from the wave "
              f"diagram's {x_spall * 1e3:g} mm (h = {H * 1e6:.2f} um)")
        a, t = load(snaps[-1])
        X0 = np.array([x0[i] for i in a["id"]])
        failed = (a["body"] == 1) & (a["damage"] >= 1.0)
        scab = (a["body"] == 1) & (X0 > X0[failed].max())
        v = float(np.mean(a["velocity"][scab, 0]))
        check(abs(v - speed) <= 0.05 * speed,
              f"{label}: scab ({scab.sum()} particles) at {v:.2f} m/s at {t * 1e6:.1f} us "
              f"(flyer {speed:g} m/s)")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
