#!/usr/bin/python3
"""The porous aluminium Hugoniot (decks/porous_aluminium_hugoniot_1d.toml; issue 16).

A slab at distension alpha0 = 1.4 hits a rigid wall at up. Ahead of the compaction shock runs an
elastic precursor to the elastic pressure Pe at fixed alpha0; the compaction shock takes the
precursor's state (rho_e, u_e, Pe, e_e) to rest on the wall (u2 = up in the slab's frame):
  P2 - Pe = rho_e (U2 - u_e)(up - u_e),  rho2 = rho_e (U2 - u_e)/(U2 - up),
  e2 = e_e + (P2 + Pe)(1/rho_e - 1/rho2)/2,
  P2 = P_eos(alpha2 rho2, e2)/alpha2 with alpha2 = alpha_c(P2)  (materials/Porosity.hpp),
and the precursor the same from rest with alpha = alpha0 and P = Pe. Both are solved here by
bisection, with spall's Mie-Gruneisen (materials/Eos.hpp) re-implemented. Measured at t = 8 us in
the plateau (the middle half between the wall and the shock: away from the wall's heating and the
shock's width): P2, rho2, alpha2, and the shock speed U2 from the front's positions at 6 and 8 us
(where P crosses (P2 + Pe)/2, in the particles' initial positions: the slab's frame), at 100 m/s
(partial compaction, alpha2 = 1.26), 200 m/s (1.14) and 1000 m/s (full, 6.1 GPa).
Tolerances: P2 and rho2 within 1.5% (measured worst: P +0.8% at 1000 m/s, rho 0.05%); alpha2
within 3% of alpha0 - 1 (measured 0.13%); U2 within 2% (measured -1.25% at 100 m/s, -1.2% at
200, -0.4% at 1000). The partial compaction shock is weakly nonlinear: its speed runs from 953
m/s (the crush branch's acoustic speed just above Pe) to 1056 m/s at P2, so the artificial
viscosity (scaled by the matrix's 5350 m/s sound speed) spreads it over ~75 spacings, and the
profile is still steepening at 8 us (1.4% slow at 4 us): its mid-pressure point lags the steady
speed. The compaction is irreversible: no particle's alpha grows between snapshots. And with
elastic_sound_speed (Herrmann's elastic distension), a weak impact stays elastic and runs at c_e.
Extra arguments (e.g. --set run.resolution=2) go to every run, except --speeds=A,B,... (the
piston speeds of the Hugoniot cases).

With the material point method (`porous_hugoniot_mpm`: --set solver.method=mpm and the shock
viscosity that decks/README recommends for impacts, 100 and 200 m/s) the same bounds hold
(measured: P -0.10% / -0.26%, rho -0.01% / -0.02%, U +0.03% / -0.34%, alpha2 within 0.05% of
alpha0 - 1; elastic P and U within 0.04%). At 1000 m/s (full compaction) MPM's mean state is
right but its points alternate within each cell (decks/topics/mpm.md), so
that case is left out there.

usage: test_porous_hugoniot.py SPALL SOURCE_DIR [--speeds=A,B] [--set K=V ...]
"""
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
# --speeds=A,B,...: the piston speeds of the Hugoniot cases (default 100, 200 and 1000 m/s).
SPEEDS = next((tuple(float(v) for v in a.split("=", 1)[1].split(",")) for a in sys.argv[3:]
               if a.startswith("--speeds=")), (100.0, 200.0, 1000.0))
EXTRA = [a for a in sys.argv[3:] if not a.startswith("--speeds=")]
DECK = SRC / "decks" / "porous_aluminium_hugoniot_1d.toml"

# The deck's material (checked against the deck below).
from porous_aluminium import ALPHA0, C0, PE, RHO_S, curve, p_eos  # noqa: E402

failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def bisect(f, lo, hi):
    flo = f(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (f(mid) > 0) == (flo > 0):
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def shock(rho_a, u_a, p_a, e_a, u_b, alpha_of):
    """The shock from state a to particle velocity u_b: (U, P, rho, e, alpha)."""
    def state(U):
        P = p_a + rho_a * (U - u_a) * (u_b - u_a)
        rho = rho_a * (U - u_a) / (U - u_b)
        e = e_a + 0.5 * (P + p_a) * (1 / rho_a - 1 / rho)
        return P, rho, e, alpha_of(P)

    def residual(U):
        P, rho, e, al = state(U)
        return p_eos(al * rho, e) / al - P

    U = bisect(residual, u_b + 1e-6 * (u_b - u_a), u_b + 100 * (u_b - u_a) + 2e4)
    return (U,) + state(U)


def hugoniot(up):
    # precursor: fixed alpha0 to Pe (its particle velocity by bisection)
    def pre(u):
        return shock(RHO_S / ALPHA0, 0.0, 0.0, 0.0, u, lambda P: ALPHA0)[1] - PE
    ue = bisect(pre, 1e-9, up)
    Ue, Pe, rho_e, e_e, _ = shock(RHO_S / ALPHA0, 0.0, 0.0, 0.0, ue, lambda P: ALPHA0)
    U2, P2, rho2, e2, al2 = shock(rho_e, ue, Pe, e_e, up, curve)
    if U2 >= Ue:  # one shock overruns the precursor
        U2, P2, rho2, e2, al2 = shock(RHO_S / ALPHA0, 0.0, 0.0, 0.0, up, curve)
    return dict(U=U2, P=P2, rho=rho2, e=e2, alpha=al2, Ue=Ue)


def load(path):
    with h5py.File(path, "r") as f:
        g = f["particles"]
        return {k: g[k][()] for k in ("id", "position", "density", "pressure", "porosity_alpha",
                                      "specific_internal_energy")}, float(f.attrs["time"])


# The deck and the library materials it starts from (decks/materials/NAME.toml).
deck_text = DECK.read_text()
deck_text += "".join((DECK.parent / "materials" / f"{name}.toml").read_text()
                     for name in re.findall(r'^library = "(\w+)"', deck_text, re.M))
for token in ("alpha0 = 1.4", "elastic_pressure = 2.0e6", "solid_pressure = 1.0e9",
              "exponent = 2.0", "c0 = 5350.0, s = 1.34, gamma0 = 2.0", "density = 2703.0"):
    check(token in deck_text, f"the deck has {token}")

def crossing(frame, X0, level):
    """Where the pressure first falls below `level` going out from the wall, in the particles'
    initial positions (X0: id -> x at t = 0; linear between the two particles either side), and
    the current position of the first particle below it."""
    o = np.argsort(frame["position"][:, 0])
    X = np.array([X0[i] for i in frame["id"][o].tolist()])
    P = frame["pressure"][o]
    k = int(np.argmax(P < level))
    return X[k - 1] + (X[k] - X[k - 1]) * (P[k - 1] - level) / (P[k - 1] - P[k]), \
        float(frame["position"][o[k], 0])


print("up (m/s) | quantity | exact | run | error")
with tempfile.TemporaryDirectory() as tmp:
    for up in SPEEDS:
        ref = hugoniot(up)
        out = Path(tmp) / f"up{up:g}"
        cmd = [SPALL, "run", str(DECK), "--output", str(out), "--quiet",
               "--set", f"body.slab.velocity=[{-up}]", "--set", "run.end_time=8e-6",
               "--set", "output.every=2e-6"] + EXTRA
        p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
        check(p.returncode == 0, f"{up:g} m/s: the run succeeds ({p.stderr.strip()[-300:]})")
        if p.returncode:
            continue
        snaps = sorted((out / "snapshots").glob("snap_*.h5"))
        frames = [load(s) for s in snaps]
        # The shock: where P crosses (P2 + Pe)/2, first from the wall, in the particles' initial
        # positions X (the slab's frame: the material ahead is at rest there, so U = dX_s/dt).
        d0 = frames[0][0]
        X0 = dict(zip(d0["id"].tolist(), d0["position"][:, 0].tolist()))

        mid = 0.5 * (ref["P"] + PE)
        (d3, t3), (d4, t4) = frames[-2], frames[-1]
        (X3, _), (X4, xs4) = crossing(d3, X0, mid), crossing(d4, X0, mid)
        U = (X4 - X3) / (t4 - t3)
        x = d4["position"][:, 0]
        band = (x > 0.25 * xs4) & (x < 0.75 * xs4)
        run = dict(U=U, P=d4["pressure"][band].mean(), rho=d4["density"][band].mean(),
                   alpha=d4["porosity_alpha"][band].mean())
        for key, tol in (("P", 0.015), ("rho", 0.015), ("U", 0.02)):
            err = run[key] / ref[key] - 1
            print(f"{up:6g} | {key:5s} | {ref[key]:.6g} | {run[key]:.6g} | {err:+.4f}")
            check(abs(err) < tol, f"{up:g} m/s: {key} within {tol:.1%} ({err:+.4f})")
        err = (run["alpha"] - ref["alpha"]) / (ALPHA0 - 1)
        print(f"{up:6g} | alpha | {ref['alpha']:.6g} | {run['alpha']:.6g} | {err:+.4f} of alpha0-1")
        check(abs(err) < 0.03, f"{up:g} m/s: alpha2 within 3% of alpha0 - 1 ({err:+.4f})")
        # irreversibility: alpha never grows along a particle's history
        grow = 0.0
        for (a, _), (b, _) in zip(frames, frames[1:]):
            oa, ob = np.argsort(a["id"]), np.argsort(b["id"])
            grow = max(grow, float(np.max(b["porosity_alpha"][ob] - a["porosity_alpha"][oa])))
        check(grow <= 0.0, f"{up:g} m/s: no particle's alpha grows between snapshots ({grow:.3g})")

    # Elastic distension (elastic_sound_speed c_e = 2000 m/s, 37% of the matrix's): at 0.3 m/s the
    # slab stays below Pe and the wave runs at c_e, not at the matrix's 5350 m/s (which would
    # give 3.1 MPa > Pe and crush it). Exact for the model (materials/Porosity.hpp, Eq. 2, alpha_p
    # = alpha0): the same jump conditions with alpha = alpha0 + a0 P, a0 = alpha0^2/K_s (1 -
    # (c_s0/c_e)^2). Tolerances: P within 1.5%, U within 2% (the front's mid-pressure point,
    # spread by the viscosity: measured -1.2%), the pores' elastic closing alpha0 - alpha within
    # 3% (measured 0.0%: P and alpha are exact where the state is uniform).
    CE, up = 2000.0, 0.3
    a0 = ALPHA0**2 / (RHO_S * C0**2) * (1 - (C0 / CE) ** 2)
    Ue, Pel, rho_el, _, alpha_el = shock(RHO_S / ALPHA0, 0.0, 0.0, 0.0, up,
                                         lambda P: ALPHA0 + a0 * P)
    out = Path(tmp) / "elastic"
    cmd = [SPALL, "run", str(DECK), "--output", str(out), "--quiet", "--set",
           f"body.slab.velocity=[{-up}]", "--set", "run.end_time=1.6e-5", "--set",
           "output.every=4e-6", "--set",
           f"material.porous_aluminium.porosity.elastic_sound_speed={CE}"] + EXTRA
    p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    check(p.returncode == 0, f"elastic: the run succeeds ({p.stderr.strip()[-300:]})")
    if p.returncode == 0:
        frames = [load(s) for s in sorted((out / "snapshots").glob("snap_*.h5"))]
        d0 = frames[0][0]
        X0 = dict(zip(d0["id"].tolist(), d0["position"][:, 0].tolist()))

        def wave(d):
            return crossing(d, X0, 0.5 * Pel)[0]
        (d1, t1), (d2, t2) = frames[1], frames[2]  # 4 and 8 us: the wave at 8 and 16 mm
        U = (wave(d2) - wave(d1)) / (t2 - t1)
        x = d2["position"][:, 0]
        band = x < 0.5 * wave(d2)
        P, alpha = d2["pressure"][band].mean(), d2["porosity_alpha"][band].mean()
        for key, got, want, tol in (("P", P, Pel, 0.015), ("U", U, Ue, 0.02),
                                    ("closing", ALPHA0 - alpha, ALPHA0 - alpha_el, 0.03)):
            err = got / want - 1
            print(f"elastic | {key:7s} | {want:.6g} | {got:.6g} | {err:+.4f}")
            check(abs(err) < tol, f"elastic: {key} within {tol:.1%} ({err:+.4f})")
        check(Pel < PE and abs(Ue / CE - 1) < 0.01, f"elastic: the exact wave is elastic "
              f"(P {Pel:.3g} Pa < Pe) at ~c_e ({Ue:.1f} m/s)")

    # A body at rest under initial_pressure with elastic distension starts at alpha0 + a0 P0
    # (Eq. 2) and at that pressure: the interior holds P0 to round-off of the energy inversion
    # (1e-9) while the free ends release.
    out = Path(tmp) / "prestressed"
    P0 = 1.0e6
    cmd = [SPALL, "run", str(DECK), "--output", str(out), "--quiet", "--set",
           "body.slab.velocity=[0.0]", "--set", f"body.slab.initial_pressure={P0}", "--set",
           "run.end_time=1e-7", "--set", "output.every=1e-7", "--set",
           f"material.porous_aluminium.porosity.elastic_sound_speed={CE}"] + EXTRA
    p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    check(p.returncode == 0, f"prestressed: the run succeeds ({p.stderr.strip()[-300:]})")
    if p.returncode == 0:
        d, _ = load(sorted((out / "snapshots").glob("snap_*.h5"))[-1])
        x = d["position"][:, 0]
        inner = (x > 0.01) & (x < 0.03)
        dp = float(np.max(np.abs(d["pressure"][inner] / P0 - 1)))
        dal = float(np.max(np.abs(d["porosity_alpha"][inner] - (ALPHA0 + a0 * P0))))
        check(dp < 1e-9 and dal < 1e-12, f"prestressed: P0 held inside ({dp:.1e}), alpha = "
              f"alpha0 + a0 P0 ({dal:.1e})")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
