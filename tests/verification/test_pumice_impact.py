#!/usr/bin/python3
"""An aluminium projectile into pumice at 2.58 km/s (decks/pumice_impact_2d.toml; issue 16).

P-alpha in a 2D impact, with strength and flaws, on 2 ranks at the shipped resolution, to 5 us
(~10 s; at half resolution the projectile is 6 particles across and the compacted layer ahead of
it is not resolved: U/U_H 0.62-0.72):
- the compaction front on the axis moves as the porous Hugoniot says: between snapshots 1 us
  apart (2-5 us), its speed U against U_H(u), the Hugoniot of pumice at the particle velocity u
  just behind it (solved here: Rankine-Hugoniot from rest, P = P_eos(alpha rho, e)/alpha with
  alpha = alpha_c(P), spall's Tillotson re-implemented). Within 15%: the front decelerates with
  the projectile and is curved, U is a difference over 1 us and u an average over a millimetre;
  measured 0.88-0.98, see the table this prints;
- irreversibility: no particle's distension grows between snapshots;
- no particle above the crush curve: alpha <= alpha_c(P) + 0.05 (the material update puts alpha on
  the curve at the density it sees; the step's final evaluation at the kick-corrected density
  moves P, alpha stays until the next update: measured 0.027 at most; a broken compaction would
  leave alpha up to 2 above the curve);
- the far field: beyond the elastic precursor's reach (c_L = sqrt(K_s/rho_s + 4G/(3 rho)) = 3.79 km/s, x 5 us + 2 mm) alpha is 3 exactly;
- mass, momentum and total energy conserved (history.csv; energy to 1e-3 of the kinetic energy,
  the explicit integrator's drift; measured in the table).

usage: test_pumice_impact.py SPALL SOURCE_DIR
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
DECK = SRC / "decks" / "pumice_impact_2d.toml"

RHO_S, A, B, E0, a, b = 2700.0, 2.67e10, 2.67e10, 4.87e8, 0.5, 1.5
ALPHA0, PE, PS, N = 3.0, 1.0e6, 213.0e6, 2.0

failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def p_tillotson(rho, e):
    """spall's Tillotson, compressed / cold branch (materials/Eos.hpp)."""
    eta = rho / RHO_S
    mu = eta - 1
    w = e / (E0 * eta * eta) + 1
    return (a + b / w) * rho * e + A * mu + B * mu * mu


def curve(P):
    P = np.asarray(P, dtype=float)
    t = np.clip((PS - P) / (PS - PE), 0.0, 1.0)
    return 1 + (ALPHA0 - 1) * t**N


def hugoniot_speed(u):
    """U_H(u): the porous pumice Hugoniot from rest."""
    rho00 = RHO_S / ALPHA0

    def r(U):
        P = rho00 * U * u
        rho = rho00 * U / (U - u)
        al = float(curve(P))
        return p_tillotson(al * rho, 0.5 * u * u) / al - P

    lo, hi = u * (1 + 1e-9), 50 * u
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if r(mid) > 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


deck = DECK.read_text()
for token in ("alpha0 = 3.0, elastic_pressure = 1.0e6, solid_pressure = 213.0e6, exponent = 2.0",
              "A = 2.67e10, B = 2.67e10", "e0 = 4.87e8", "a = 0.5, b = 1.5"):
    check(token in deck, f"the deck has {token}")

with tempfile.TemporaryDirectory() as tmp:
    out = Path(tmp) / "run"
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", SPALL, "run", str(DECK),
           "--output", str(out), "--quiet",
           "--set", "run.end_time=5e-6"]
    p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    check(p.returncode == 0, f"the run succeeds ({p.stderr.strip()[-300:]})")
    if p.returncode:
        sys.exit(1)
    frames = []
    for s in sorted((out / "snapshots").glob("snap_*.h5")):
        with h5py.File(s, "r") as f:
            g = f["particles"]
            d = {k: g[k][()] for k in ("id", "position", "velocity", "pressure", "porosity_alpha")}
            o = np.argsort(d["id"])
            frames.append(({k: v[o] for k, v in d.items()}, float(f.attrs["time"])))
    target = frames[0][0]["porosity_alpha"] > 1.0  # the pumice (the aluminium has alpha 1)

    print("t (us) | front (mm) | U (m/s) | u (m/s) | U_H(u) | U/U_H")
    prev = None
    for d, t in frames:
        x, al = d["position"], d["porosity_alpha"]
        axis = np.abs(x[:, 0]) < 0.0006
        if not (axis & target & (al < 2.0)).any():
            continue
        front = x[axis & target & (al < 2.0), 1].min()
        behind = axis & target & (x[:, 1] > front) & (x[:, 1] < front + 0.001) & (al < 1.5)
        u = -d["velocity"][behind, 1].mean()
        if prev and 1.5e-6 < t < 5.5e-6:
            U = (prev[0] - front) / (t - prev[1])
            um = 0.5 * (u + prev[2])
            UH = hugoniot_speed(um)
            print(f"{t * 1e6:6.1f} | {front * 1e3:10.2f} | {U:7.0f} | {um:7.0f} | {UH:6.0f} | {U / UH:.3f}")
            check(abs(U / UH - 1) < 0.15, f"t = {t * 1e6:.0f} us: the front's speed within 15% of "
                                          f"the porous Hugoniot's ({U / UH:.3f})")
        prev = (front, t, u)

    grow = 0.0
    for (da, _), (db, _) in zip(frames, frames[1:]):
        grow = max(grow, float(np.max(db["porosity_alpha"] - da["porosity_alpha"])))
    check(grow <= 0.0, f"no particle's alpha grows between snapshots (largest change {grow:.3g})")

    above = max(float(np.max((d["porosity_alpha"] - curve(d["pressure"]))[target]))
                for d, _ in frames)
    check(above <= 0.05, f"alpha <= alpha_c(P) + 0.05 in every snapshot (largest excess {above:.3g})")

    d, t = frames[-1]
    far = target & (np.hypot(d["position"][:, 0], d["position"][:, 1]) > 3786.0 * t + 0.002)
    check(far.any() and bool(np.all(d["porosity_alpha"][far] == ALPHA0)),
          f"{far.sum()} particles beyond the precursor's reach keep alpha = 3 exactly")

    h = np.genfromtxt(out / "history.csv", delimiter=",", names=True)
    ke = np.max(np.abs(h["kinetic_energy"]))
    mom = float(np.max(np.abs(h["momentum_y"] - h["momentum_y"][0]))) / float(
        np.max(np.abs(h["momentum_y"])))
    en = float(np.max(np.abs(h["total_energy"] - h["total_energy"][0]))) / ke
    mass = float(np.max(np.abs(h["mass"] - h["mass"][0]))) / h["mass"][0]
    check(mass < 1e-12, f"mass conserved to the round-off of its sum ({mass:.1e})")
    check(mom < 1e-12, f"momentum conserved ({mom:.1e} of the projectile's)")
    check(en < 1e-3, f"total energy conserved ({en:.1e} of the kinetic energy)")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
