#!/usr/bin/python3
"""Rate dependence of the cap model (materials/CapPlasticity.hpp: Arenisca's Duvaut-Lions
overstress, tau = T1 (1/|D|)^T2) through the single-element driver, on a strain-rate jump.

The path: an isochoric stretch F = diag(e^a, e^-a, 1) (D = diag(a', -a', 0), |D| = sqrt2 a',
no rotation, no volume change), a' = 100 /s for 20 us, then 1000 /s for 10 us, then held for
30 us. The material is tests/verification/element/cap.toml's linear Drucker-Prager `dp` with no
dilatancy: I1 stays 0, so the quasi-static stress yields at q_y = f_slope peak_i1 and stays there
(q = sqrt(J2) = S11 on this path). The overstress y = q - q_y then obeys dy/dt = 2 G a' - y/tau
past the yield, whose solution over a stretch of constant rate is
    y(t) = y0 e^-(t - t0)/tau + 2 G a' tau (1 - e^-(t - t0)/tau),
and the model's update integrates exactly that for rates constant over a step. Checked at every
step (dt = 10 ns, a row of the table each: between rows the driver interpolates F linearly, which
would bend the exponential path by 1e-3 of a row's stretch):
- T2 = 0 (tau = T1 = 3 us at any rate): q against the exact y(t) through the jump (steady
  overstress 2 G a' tau: 9 MPa, then 90 MPa) and the hold, where the overstress decays as
  e^-t/tau to the rate-independent q_y. Tolerance 1e-4 q_y: the step in which yield begins
  integrates the whole step's trial increment from where the step starts, an error of at most
  2 G a' dt^2 / tau = 200 Pa (2e-5 q_y) that then decays; the midpoint kinematics' rate
  2 tanh(a' dt/2)/dt is a' within (a' dt)^2/12 = 1e-11.
- T2 = 0.5 (T1 set so that tau = 3 us at 100 /s): tau 0.949 us at 1000 /s, the steady overstress
  at the end of the fast leg 10^0.5 = 3.16 times larger in rate times tau: the exact solution
  again within 1e-4 q_y; held still (|D| = 0, tau practically infinite), the overstress stays.
- The rate-independent limit: T1 = 1e-15 s (tau far below the step) gives the rate-independent
  run's q (T1 = 0) within 1e-8 q_y (the steady overstress 2 G a' tau is 0.03 Pa, 3.3e-9 q_y).
- The I1 overstress: none on this path (no plastic volume change): I1 = 0 within 1e-6 q_y.
- A negative T1 or T2 is a deck error (exit 2).
Plot (PNG): q against time, the three runs and the exact curves, in ./cap_rate_plots.

usage: test_cap_rate.py SPALL SOURCE_DIR
"""
import csv
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from plots import save_plot

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
DECK = SRC / "tests" / "verification" / "element" / "cap.toml"
PLOTS = Path.cwd() / "cap_rate_plots"
G, FS, PEAK = 15.0e9, 0.435438, 20.99e6
QY = FS * PEAK
LEGS = [(20e-6, 100.0), (10e-6, 1000.0), (30e-6, 0.0)]  # (duration, a')
ROW = 1e-8  # a row per step (--substeps 1): the driver interpolates F linearly between rows
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def table(path):
    t, a, rows = 0.0, 0.0, []
    rows.append((0.0, 0.0))
    for length, rate in LEGS:
        for k in range(1, int(round(length / ROW)) + 1):
            rows.append((t + k * ROW, a + rate * k * ROW))
        t += length
        a += rate * length
    with open(path, "w") as f:
        f.write("# isochoric stretch diag(e^a, e^-a, 1): a' 100 /s, 1000 /s, then held\n")
        for t, a in rows:
            f.write(f"{t:.17g} {math.exp(a):.17g} 0 0  0 {math.exp(-a):.17g} 0  0 0 1\n")


def drive(tab, out, *sets, expect=0):
    cmd = [SPALL, "element", str(DECK), "--material", "dp", "--table", str(tab), "--output",
           str(out), "--kinematics", "midpoint", "--substeps", "1",
           "--set", "material.dp.strength.dilatancy=0"]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    if p.returncode != expect:
        check(False, f"{' '.join(cmd[1:])}: exit {p.returncode}, expected {expect}\n{p.stderr}")
        return None
    if expect != 0:
        return p
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def tau_of(T1, T2, rate):
    if T2 == 0.0:
        return T1
    return T1 * (1.0 / max(math.sqrt(2.0) * rate, 1e-15)) ** T2


def exact(t, T1, T2):
    """q(t): elastic 2 G a to q_y, then q_y + y with y from the ODE, leg by leg."""
    q = np.empty_like(t)
    t0, a0, y0, yielded = 0.0, 0.0, 0.0, False
    for length, rate in LEGS:
        sel = (t >= t0 - 1e-15) & (t <= t0 + length + 1e-15)
        s = t[sel] - t0
        tau = tau_of(T1, T2, rate)
        if not yielded:
            a = a0 + rate * s
            ty = (QY / (2.0 * G) - a0) / rate if rate > 0 else math.inf
            el = s < ty
            out = np.where(el, 2.0 * G * a, 0.0)
            d = np.maximum(s - ty, 0.0)
            out = np.where(el, out, QY + 2.0 * G * rate * tau * -np.expm1(-d / tau))
            q[sel] = out
            if ty <= length:
                yielded = True
                d = length - ty
                y0 = 2.0 * G * rate * tau * -np.expm1(-d / tau)
        else:
            e = np.exp(-s / tau)
            q[sel] = QY + y0 * e + 2.0 * G * rate * tau * (1.0 - e)
            e1 = math.exp(-length / tau)
            y0 = y0 * e1 + 2.0 * G * rate * tau * (1.0 - e1)
        t0 += length
        a0 += rate * length
    return q


def q_of(r):
    return np.sqrt(0.5 * ((r["sxx"] - r["syy"]) ** 2 + (r["syy"] - r["szz"]) ** 2 +
                          (r["szz"] - r["sxx"]) ** 2) / 3.0 + r["sxy"] ** 2 + r["syz"] ** 2 +
                   r["sxz"] ** 2)


def main(tmp):
    tab = tmp / "jump.ftable"
    table(tab)
    runs = {}
    T1c = 3e-6
    T1p = 3e-6 * math.sqrt(math.sqrt(2.0) * 100.0)  # tau = 3 us at 100 /s with T2 = 0.5
    cases = [("T2 = 0, tau 3 us", T1c, 0.0), ("T2 = 0.5", T1p, 0.5)]
    for label, T1, T2 in cases:
        r = drive(tab, tmp / f"{T2}.csv", f"material.dp.strength.rate_t1={T1!r}",
                  f"material.dp.strength.rate_t2={T2!r}")
        if r is None:
            continue
        runs[label] = r
        q, qe = q_of(r), exact(r["t"], T1, T2)
        err = np.max(np.abs(q - qe))
        check(err <= 1e-4 * QY, f"{label}: q against the exact overstress at every substep: "
                                f"max |error| {err:.3g} Pa = {err / QY:.2e} q_y (bound 1e-4)")
        I1 = r["sxx"] + r["syy"] + r["szz"]
        check(np.max(np.abs(I1)) <= 1e-6 * QY, f"{label}: I1 = 0 within 1e-6 q_y "
                                               f"(max {np.max(np.abs(I1)):.2e} Pa)")
        fast_end = np.argmin(np.abs(r["t"] - 30e-6))
        slow_end = np.argmin(np.abs(r["t"] - 20e-6))
        y_fast, y_slow = q[fast_end] - QY, q[slow_end] - QY
        ex = exact(np.array([20e-6, 30e-6]), T1, T2) - QY
        print(f"     {label}: overstress {y_slow / 1e6:.3f} MPa at 100 /s, {y_fast / 1e6:.3f} "
              f"MPa at 1000 /s (ratio {y_fast / y_slow:.3f}; exact {ex[1] / ex[0]:.3f}; steady "
              f"rate x tau {1000.0 * tau_of(T1, T2, 1e3) / (100.0 * tau_of(T1, T2, 1e2)):.3f})")
        end = q[-1] - QY
        if T2 == 0.0:
            decay = math.exp(-30e-6 / T1)
            check(abs(end - y_fast * decay) <= 1e-4 * QY,
                  f"{label}: held 30 us, the overstress decays as e^-t/tau to "
                  f"{end:.3g} Pa (expected {y_fast * decay:.3g} Pa)")
        else:
            check(abs(end / y_fast - 1.0) <= 1e-6,
                  f"{label}: held still (|D| = 0), the overstress stays ({end / 1e6:.4f} MPa "
                  f"against {y_fast / 1e6:.4f})")
    qs = drive(tab, tmp / "qs.csv")
    lim = drive(tab, tmp / "lim.csv", "material.dp.strength.rate_t1=1e-15")
    if qs is not None and lim is not None:
        d = np.max(np.abs(q_of(qs) - q_of(lim)))
        check(d <= 1e-8 * QY, f"T1 = 1e-15 s against the rate-independent run: max |dq| "
                              f"{d:.2e} Pa (bound 1e-8 q_y)")
        check(abs(q_of(qs)[-1] / QY - 1.0) < 1e-9, "the rate-independent run ends at q_y")
        runs["rate-independent"] = qs
    for key, value in (("rate_t1", "-1e-6"), ("rate_t2", "-0.5")):
        p = drive(tab, tmp / "bad.csv", f"material.dp.strength.{key}={value}", expect=2)
        check(p is not None and key in p.stderr, f"{key} = {value}: exit 2 naming the key")

    def plot(ax):
        for label, r in runs.items():
            ax.plot(r["t"] * 1e6, q_of(r) / 1e6, label=f"spall element, {label}")
        for label, T1, T2 in cases:
            t = np.linspace(0.0, 60e-6, 600)
            ax.plot(t * 1e6, exact(t, T1, T2) / 1e6, "k:", lw=1)
        ax.set_xlabel("t (us)")
        ax.set_ylabel("q = sqrt(J2) (MPa)  [dotted: exact]")
    save_plot(PLOTS, "cap_rate_jump", plot)


with tempfile.TemporaryDirectory() as d:
    main(Path(d))
print(f"\n{len(failures)} failure(s)" if failures else "\nall passed")
sys.exit(1 if failures else 0)
