#!/usr/bin/python3
"""spall.penetration (the figures tools/penetration prints) against closed forms and synthetic
runs whose answers are known by construction; no binary needed.

- Alekseevskii-Tate with Y_p = R_t = 0: the Bernoulli rate for the whole rod, depth
  L sqrt(rho_p/rho_t) (1e-9: an RK4 integration of a constant rate is exact to round-off).
- Tate with rho_p = rho_t and Y_p = R_t = Y: u = v/2, so dl/dv = rho l v / (2Y) and
  P = L (1 - exp(-rho V^2 / (4Y))) (the integration's error at 20,000 steps is ~1e-8; 1e-6).
- Tate with a rigid rod (Y_p >= 1/2 rho_t V^2 + R_t): u = V, no erosion, and the rod stops where
  rho_p L dv/dt = -(R_t + 1/2 rho_t v^2): P = rho_p L / rho_t ln(1 + rho_t V^2 / (2 R_t)).
- Lanz-Odermatt: 0.829 for tungsten alloy (17,600) into steel (7,830, BHN 300) at 1.5 km/s,
  L/D 10: the issue's experiment (0.83) to the fit's three figures.
- A synthetic run: depth = U t with the staircase of 0.25 mm particle layers and 2% noise, then a
  deceleration to rest and a rebound of a tenth of a millimetre: the detected window lies past
  two diameters and ends where the tolerance lets the deceleration in, its rate U within half the
  tolerance (5% and 10%); the arrest at the row where the last layer is reached; the residual
  velocity 0; the maximum depth the deepest row, not the rebounded last one.
- A run still moving at its end: no arrest, residual velocity None, a note that says so.
- U = a + b V over four synthetic runs with known scatter: a and b and their standard errors as
  numpy's weighted polyfit covariance gives them (1e-9); a run with no steady rate left out with
  its reason; two runs: a and b with no errors, said so.
- JSON: a result with a missing figure serialises with allow_nan=False (null, never NaN).
- L: a union's parts along the direction without their gaps (a jet as it flies), overlaps
  counted once; a target's span with its gaps.

usage: test_penetration_analysis.py SOURCE_DIR
"""
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

SRC = Path(sys.argv[1])
sys.path.insert(0, str(SRC / "tools" / "python"))
import spall.penetration as pen  # noqa: E402

failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def tate_closed_forms():
    V, L, rho_p, rho_t = 1500.0, 0.04, 17600.0, 7830.0
    t = pen.tate(V, L, rho_p, rho_t, 0.0, 0.0)
    Ph = L * math.sqrt(rho_p / rho_t)
    check(abs(t["depth"] / Ph - 1.0) < 1e-9,
          f"Tate, no strength: depth {t['depth']:.9g} = L sqrt(rho_p/rho_t) {Ph:.9g}")
    check(abs(t["U0"] / pen.bernoulli_rate(V, rho_p, rho_t) - 1.0) < 1e-12,
          "Tate, no strength: the initial rate is Bernoulli's")
    rho, Y = 7830.0, 1.0e9
    t = pen.tate(V, L, rho, rho, Y, Y)
    P = L * (1.0 - math.exp(-rho * V * V / (4.0 * Y)))
    check(abs(t["depth"] / P - 1.0) < 1e-6,
          f"Tate, rho_p = rho_t, Y_p = R_t: depth {t['depth'] * 1e3:.6f} mm against the closed "
          f"form {P * 1e3:.6f} mm")
    Rt = 2.0e9
    t = pen.tate(500.0, L, rho_p, rho_t, 5.0e9, Rt)
    P = rho_p * L / rho_t * math.log(1.0 + rho_t * 500.0**2 / (2.0 * Rt))
    check(t["U0"] == 500.0 and abs(t["depth"] / P - 1.0) < 1e-5,
          f"Tate, a rigid rod: u = V, depth {t['depth'] * 1e3:.5f} mm against "
          f"{P * 1e3:.5f} mm, length kept {t['residual_length'] / L:.6f} L")
    lo = pen.lanz_odermatt(1500.0, 10.0, 17600.0, 7830.0, 300.0)
    check(abs(lo - 0.829) < 5e-4, f"Lanz-Odermatt at 1.5 km/s, L/D 10, BHN 300: P/L {lo:.4f} "
                                  f"(the experiments 0.83)")


def write_run(d, t, depth, tip, V, L=0.04, D=0.004, status="finished"):
    """A run directory as spall writes it: deck.toml, penetration.csv, summary.json."""
    d.mkdir(parents=True)
    (d / "deck.toml").write_text(f"""
[run]
dimension = 2
geometry = "rz"
[[material]]
name = "w"
density = 17600.0
[[material]]
name = "st"
density = 7830.0
[[body]]
name = "rod"
material = "w"
shape = {{ type = "box", min = [0.0, 0.0], max = [{D / 2}, {L}] }}
velocity = [0.0, {-V}]
[[body]]
name = "target"
material = "st"
shape = {{ type = "box", min = [0.0, -0.08], max = [0.06, 0.0] }}
[penetration]
penetrator = ["rod"]
target = "target"
surface = [0.0, 0.0]
direction = [0.0, -1.0]
""")
    rows = ["time,depth,rate,tip_velocity"]
    rate = np.gradient(depth, t)
    rows += [f"{a:.17g},{b:.17g},{c:.17g},{e:.17g}" for a, b, c, e in zip(t, depth, rate, tip)]
    (d / "penetration.csv").write_text("\n".join(rows) + "\n")
    (d / "summary.json").write_text(json.dumps({"status": status, "wall_seconds": 1.0}))


def synthetic(tmp):
    rng = np.random.default_rng(3)
    V, U, D = 1500.0, 700.0, 0.004
    t = np.linspace(0.0, 100e-6, 400)
    tstop = 50e-6
    # Steady to 35 us, then a linear fall of the rate to rest at 50 us, then a rebound.
    t1 = 35e-6
    z = np.where(t < t1, U * t, U * t1 + U * (t - t1) - 0.5 * U / (tstop - t1) * (t - t1) ** 2)
    zmax = U * t1 + 0.5 * U * (tstop - t1)
    z = np.where(t >= tstop, zmax - 1e-4 * (1.0 - np.exp(-(t - tstop) / 5e-6)), z)
    layered = np.floor(z / 2.5e-4) * 2.5e-4 + rng.normal(0.0, 0.02 * 2.5e-4, len(t))
    tip = np.where(t < tstop, V * (1.0 - t / tstop), 0.0)
    write_run(tmp / "synthetic", t, layered, tip, V)
    for tol in (0.05, 0.10):
        # A window whose last third runs x into the deceleration (the rate falling by U/T, T =
        # 15 us) has that third's rate short by U x^2/(2 T W/3), W the window's length: the
        # window may end x = sqrt(2 T tol W/3) late (W < t1 - t0 + 6 us; 15% for the noise and
        # the rows' spacing), and its slope stays within tol/2 of U.
        r = pen.analyse(tmp / "synthetic", tol=tol)
        w = r["window"]
        check(w is not None and r["U"] is not None and abs(r["U"] / U - 1.0) <= tol / 2,
              f"synthetic, tol {tol:g}: steady U {r['U']:.1f} within {50 * tol:g}% of {U:.0f} "
              f"m/s ({r['window_reason']})")
        late = 1.15 * math.sqrt(2.0 * (tstop - t1) * tol * (t1 - w[0] + 6e-6) / 3.0)
        check(w is not None and U * w[0] >= 2.0 * D - 2.6e-4 and w[1] <= t1 + late,
              f"synthetic, tol {tol:g}: the window {w[0] * 1e6:.2f}-{w[1] * 1e6:.2f} us starts "
              f"past two diameters and ends by {(t1 + late) * 1e6:.2f} us")
    # The rod gains less than 1% of a diameter after t_a: on the layer staircase that is when
    # the last layer is reached (a layer, 0.25 mm, is more than 0.01 D).
    expect = t[np.argmax(layered >= layered.max() - 0.01 * D)]
    check(r["arrest_time"] is not None and r["arrest_time"] == expect,
          f"synthetic: arrest at {r['arrest_time'] * 1e6 if r['arrest_time'] else None} us "
          f"(the last layer's {expect * 1e6:.2f} us)")
    check(r["residual_velocity"] == 0.0 and abs(r["max_depth"] - layered.max()) == 0.0 and
          r["max_depth"] > r["final_depth"],
          f"synthetic: residual velocity 0, max depth {r['max_depth'] * 1e3:.3f} mm the deepest "
          f"row, past the rebounded final {r['final_depth'] * 1e3:.3f} mm")
    # Still moving at the end.
    t = np.linspace(0.0, 20e-6, 100)
    write_run(tmp / "moving", t, U * t, np.full(len(t), V), V)
    r = pen.analyse(tmp / "moving")
    check(r["arrest_time"] is None and r["residual_velocity"] is None and
          any("still penetrating" in n for n in r["notes"]),
          f"moving: no arrest, no residual velocity, said ({r['notes']})")
    json.dumps(pen.jsonable({k: v for k, v in r.items() if k != "series"}), allow_nan=False)
    check(True, "moving: its result serialises with allow_nan=False")


def fits(tmp):
    a, b = -120.0, 0.64
    speeds = [1500.0, 2000.0, 2500.0, 3000.0]
    scatter = [4.0, -6.0, 3.0, -1.0]
    runs = []
    for V, e in zip(speeds, scatter):
        t = np.linspace(0.0, 60e-6, 300)
        d = tmp / f"fit_{V:.0f}"
        write_run(d, t, (a + b * V + e) * t, np.full(len(t), V), V, L=0.5, D=0.0015)
        runs.append(pen.analyse(d))
    t = np.linspace(0.0, 60e-6, 300)
    write_run(tmp / "shallow", t, 1e-4 * t / t[-1], np.zeros(len(t)), 1000.0, L=0.5, D=0.0015)
    runs.append(pen.analyse(tmp / "shallow"))
    f = pen.fit_rates(runs)
    U = np.array([a + b * V + e for V, e in zip(speeds, scatter)])
    coef, cov = np.polyfit(speeds, U, 1, cov=True)
    check(abs(f["b"] - coef[0]) < 1e-9 and abs(f["a"] - coef[1]) < 1e-6,
          f"U = a + b V: a {f['a']:.3f}, b {f['b']:.6f} against polyfit's {coef[1]:.3f}, "
          f"{coef[0]:.6f}")
    # numpy's cov=True scales by the residual variance over (N - 2), as fit_rates does.
    check(abs(f["b_error"] / math.sqrt(cov[0, 0]) - 1.0) < 1e-6 and
          abs(f["a_error"] / math.sqrt(cov[1, 1]) - 1.0) < 1e-6,
          f"U = a + b V: errors {f['a_error']:.3f} m/s, {f['b_error']:.6f} as polyfit's")
    check(f["runs"] == 4 and len(f["left_out"]) == 1 and "shallow" in f["left_out"][0]["run"],
          f"U = a + b V: the shallow run left out, with its reason ({f['left_out']})")
    two = pen.fit_rates(runs[:2])
    check(two["a_error"] is None and "no uncertainty" in two.get("why", ""),
          f"U = a + b V through two runs: no errors, said ({two.get('why')})")


def unreadable(tmp):
    """tools/penetration: a bad directory beside good runs is named and left out (exit 1), the
    others' table printed; a corrupt sweep.json is a clear error (exit 2), not a traceback."""
    tool = [sys.executable, str(SRC / "tools" / "penetration")]
    (tmp / "not_a_run").mkdir()
    dirs = [str(tmp / n) for n in ("fit_1500", "not_a_run", "fit_2000")]
    p = subprocess.run(tool + dirs, capture_output=True, text=True)
    check(p.returncode == 1 and "fit_1500" in p.stdout and "fit_2000" in p.stdout and
          "not_a_run" in p.stderr and "Traceback" not in p.stderr,
          f"a bad run directory left out and named, the table printed, exit 1 "
          f"(exit {p.returncode})")
    png = tmp / "rate.png"
    p = subprocess.run(tool + [str(tmp / f"fit_{V}") for V in (1500, 2000, 2500, 3000)] +
                       ["--rate-png", str(png)], capture_output=True, text=True)
    check(p.returncode == 0 and png.is_file() and png.stat().st_size > 10000,
          f"--rate-png: U against V drawn (exit {p.returncode}, "
          f"{png.stat().st_size if png.is_file() else 0} bytes)")
    (tmp / "sweep").mkdir()
    (tmp / "sweep" / "sweep.json").write_text('{"runs": [')
    p = subprocess.run(tool + [str(tmp / "sweep")], capture_output=True, text=True)
    check(p.returncode == 2 and "sweep.json" in p.stderr and "Traceback" not in p.stderr,
          f"a corrupt sweep.json: exit 2 with its name, no traceback (exit {p.returncode}: "
          f"{p.stderr.strip()[:120]})")


def lengths():
    """L along the direction: a rod with a nose is shank and nose together (they overlap); a
    union with gaps, a jet as it flies, its parts without the gaps (exact sums of box lengths,
    1e-15); a spaced target's rear face its whole span."""
    down = [0.0, -1.0]
    shank = {"type": "box", "min": [0.0, 0.0], "max": [1.0e-3, 0.04]}
    nose = {"type": "cone", "base": [0.0, 0.0], "axis": [0.0, -1.0], "radius": 1.0e-3,
            "length": 3.0e-3}
    rod = pen.extent_along({"type": "union", "shapes": [shank, nose]}, down)
    check(abs(rod - 0.043) <= 1e-15, f"a rod with a nose: L = 43 mm ({rod * 1e3:.6f} mm)")
    train = {"type": "union", "shapes": [
        {"type": "box", "min": [0.0, -0.010], "max": [1.0e-3, -0.006]},   # the tip, 4 mm
        {"type": "box", "min": [0.0, -0.005], "max": [1.2e-3, -0.002]},   # a 1 mm gap, 3 mm
        {"type": "box", "min": [0.0, -0.0025], "max": [0.8e-3, 0.001]},  # 3.5, 0.5 overlapping
        # a union inside the union: 2 mm, after a 2 mm gap
        {"type": "union", "shapes": [{"type": "box", "min": [0.0, 0.003], "max": [0.5e-3, 0.005]}]}]}
    L, span = pen.extent_along(train, down), pen.span_along(train, down)
    check(abs(L - 0.012) <= 1e-15 and abs(span - 0.015) <= 1e-15,
          f"a jet with gaps and an overlap: L = 12 mm of material ({L * 1e3:.6f}), span 15 mm "
          f"({span * 1e3:.6f})")


with tempfile.TemporaryDirectory() as d:
    lengths()
    tate_closed_forms()
    synthetic(Path(d))
    fits(Path(d))
    unreadable(Path(d))

print(f"\n{len(failures)} failure(s)" if failures else "\nall passed")
sys.exit(1 if failures else 0)
