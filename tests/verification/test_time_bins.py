#!/usr/bin/python3
"""Hierarchical time steps (solver.time_bins; methods/TimeBins.hpp, methods/SphTimeBins.cpp).

- Penetration (decks/rod_into_steel_semi_infinite_rz.toml, which ships 6 bins, at run.resolution
  0.5, 4 rings across the rod's radius, to 8 us): 6 bins against one step for all. The depth
  within 1% of the single-step run's (measured +0.001%), with at most 90% of its row
  evaluations (measured 78%: at 8 us the impact's step has not yet fallen far below the graded
  far field's; the whole run's figures are in decks/topics/solids.md). The energy with the
  booked work within 1e-3 (the issue's bound; measured 2e-5) and the momentum within 1e-3 of the
  rod's (measured 2e-5). Block steps do not keep momentum exact pair by pair: a pair across two
  bins is kicked by the fast particle's force at its times and by the slow one's at its own,
  which differ by O(delta^3 d^2F/dt^2) a step for a smooth force.
- Noh (decks/noh_2d.toml at run.resolution 0.5, graded as tests/verification/
  test_graded_spacing.py grades it): the cold inflow sits in the slowest bins until the shock
  wakes it. The post-shock density within the single-step run's error of the exact 16 plus 1%
  (measured 16.47 against 16.50). Where a shock reaches a particle within its step the pair's
  force jumps, and the mismatch above is O(delta Delta F) once a particle: the energy error is
  first order in the step. Asserted: with 2 bins it falls by at least 1.7x when cfl halves
  (measured 5.0e-4 to 1.7e-4; the single-step run's is second order, 2.3e-5 to 5.2e-6), and 6
  bins keep it under 1e-2 (measured 1.4e-3).
- One bin: an elastic bar (decks/graded_plane_wave_1d.toml ungraded, a 16.6 MPa pulse) whose
  particles' own steps all lie within a factor of 2 sits in the finest bin throughout; 6 bins
  then take the single-step run's steps, the same particles bit for bit.
- Ranks and restarts: the penetration at run.resolution 0.25 to 10 us with 6 bins on 1 rank (2
  threads), 2, 3 and 5 ranks, and on 3 ranks stopped at step 4 and restarted: the same particles
  bit for bit.

usage: test_time_bins.py SPALL SOURCE_DIR
"""
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from spalltest import Checks, differing, final_state, noh_density, rows  # noqa: E402

SRC = Path(sys.argv[2])
DECKS = SRC / "decks"
ROD = DECKS / "rod_into_steel_semi_infinite_rz.toml"
NOH = DECKS / "noh_2d.toml"

t = Checks()


def summary(out):
    return json.loads((out / "summary.json").read_text())


def depth(out):
    return float(rows(out / "penetration.csv")[-1]["depth"])


def books(out):
    """The energy with the booked work and the momentum, relative (summary.json)."""
    c = summary(out)["conservation"]
    return c["energy_relative"], c["momentum_relative"]


def penetration(tmp):
    sets = ["run.resolution=0.5", "run.end_time=8.0e-6", "output.every=4.0e-6"]
    one, six = tmp / "rod_1", tmp / "rod_6"
    if not (t.run(ROD, one, *sets, "solver.time_bins=1", ranks=2) and
            t.run(ROD, six, *sets, "solver.time_bins=6", ranks=2)):
        return
    d1, d6 = depth(one), depth(six)
    t.check(abs(d6 / d1 - 1.0) < 0.01,
            f"rod into graded steel: depth {1e3 * d6:.4f} mm with 6 bins, {1e3 * d1:.4f} mm "
            f"with one step (within 1%)")
    w1, w6 = summary(one)["time_bins"], summary(six)["time_bins"]
    fraction = w6["row_evaluations"] / w1["row_evaluations"]
    t.check(fraction < 0.9,
            f"rod: 6 bins evaluate {100 * fraction:.1f}% of the single-step run's rows "
            f"(< 90%; populations {w6['populations']})")
    energy, momentum = books(six)
    t.check(energy < 1e-3 and momentum < 1e-3,
            f"rod, 6 bins: energy with the booked work {energy:.2e}, momentum {momentum:.2e} "
            f"(each < 1e-3)")


def noh(tmp):
    common = ["run.resolution=0.5", "output.every=0.6"]
    graded = "body.gas.grading={within = 0.5, ratio = 1.05, max_spacing = 0.04, point = [0.0, 0.0]}"
    one, six = tmp / "noh_1", tmp / "noh_6"
    if not (t.run(NOH, one, *common, graded, ranks=2) and
            t.run(NOH, six, *common, graded, "solver.time_bins=6", ranks=2)):
        return
    (r1, _), (r6, _) = noh_density(one), noh_density(six)
    e1, e6 = abs(r1 / 16.0 - 1.0), abs(r6 / 16.0 - 1.0)
    t.check(e6 <= e1 + 0.01,
            f"Noh graded, 6 bins: post-shock density {r6:.3f} ({100 * e6:.1f}% from 16) within "
            f"the single-step run's {r1:.3f} ({100 * e1:.1f}%) + 1%")
    energy, _ = books(six)
    t.check(energy < 1e-2, f"Noh graded, 6 bins: energy error {energy:.2e} (< 1e-2)")
    errors = []
    for cfl in (0.25, 0.125):
        out = tmp / f"noh_2bins_{cfl}"
        if not t.run(NOH, out, *common, "solver.time_bins=2", f"solver.cfl={cfl}", ranks=2):
            return
        errors.append(books(out)[0])
    t.check(errors[0] / errors[1] > 1.7,
            f"Noh, 2 bins: the energy error falls from {errors[0]:.2e} to {errors[1]:.2e} when "
            f"cfl halves (by > 1.7x: first order)")


def one_bin(tmp):
    deck = DECKS / "graded_plane_wave_1d.toml"
    sets = ["body.bar.grading.ratio=1.0", "body.bar.grading.max_spacing=1.0e-5",
            "run.end_time=1.0e-6", "output.every=5.0e-7"]
    one, six = tmp / "bar_1", tmp / "bar_6"
    if not all(t.run_all([(deck, one, sets), (deck, six, sets + ["solver.time_bins=6"])])):
        return
    a, ta = final_state(one)
    b, tb = final_state(six)
    differ = differing(a, b)
    history = rows(six / "history.csv")
    finest = all(r["bin_0"] == r["particles"] for r in history[1:])
    t.check(finest and ta == tb and not differ and not b["time_bin"].any(),
            f"elastic bar, every particle in the finest bin ({'all' if finest else 'not all'} "
            f"steps): 6 bins and one step for all, the same particles bit for bit"
            + (f" (differ: {differ})" if differ else ""))


def ranks_and_restart(tmp):
    sets = ["run.resolution=0.25", "run.end_time=1.0e-5", "output.every=5.0e-6",
            "solver.time_bins=6", "checkpoint.every_steps=4"]
    one = tmp / "b1"
    if not t.run(ROD, one, *sets):
        return
    others = []
    for ranks in (2, 3, 5):
        if t.run(ROD, tmp / f"b{ranks}", *sets, ranks=ranks):
            others.append((f"{ranks} ranks", tmp / f"b{ranks}"))
    again = tmp / "b3_restarted"
    if (t.run(ROD, again, *sets, "run.max_steps=4", ranks=3) and
            t.run(ROD, again, *sets, ranks=3, restart="latest")):
        others.append(("3 ranks, restarted at step 4", again))
    t.same_particles(one, others, "rod, 6 bins, 1 rank (2 threads)")


with tempfile.TemporaryDirectory() as d:
    tmp = Path(d)
    penetration(tmp)
    noh(tmp)
    one_bin(tmp)
    ranks_and_restart(tmp)
t.finish()
