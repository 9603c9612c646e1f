#!/usr/bin/python3
"""Graded spacing (a [[body]]'s grading table; app/GradedSites.cpp) in runs.

- Plane-wave reflection (decks/graded_plane_wave_1d.toml, _2d.toml): a 2 mm half-sine pulse of
  16.6 MPa crosses the bar's layers, which grow from 10 um (40 um in 2D) by `ratio` per layer to
  160 um. The reflection is the left-going part, (d_sigma + rho c d_v)/2, of the difference
  between the graded bar and the same bar ungraded (ratio 1, max_spacing = spacing: the same
  particles in the fine region), largest over the fine region (0.3-3.7 mm) and the run, over the
  incident pulse's right-going amplitude. A continuum reflects nothing; SPH's operator across a
  spacing gradient is not exact, and reflects in proportion to it. Asserted: under 1% at the
  default ratio 1.05 (the issue's bound; measured 0.90% in 1D, 0.88% in 2D), and growing with the
  ratio over 1.02, 1.05, 1.1, 1.2 in 1D (measured 0.31, 0.90, 1.42, 1.87%: the same to 0.001%
  whether the uniform bar is whole or cut short where its end cannot be heard in time).
- At rest: an rz steel block graded from its axis (250 um to 2 mm), at rest and free, and under
  100 MPa (initial_pressure and a confining pressure on its surface), over 1,000 steps: the peak
  speed below 1e-6 of its sound speed (the issue's bound; measured 0 and 7e-19).
- Noh (decks/noh_2d.toml at run.resolution 0.5): graded about the centre (0.02 within 0.5, to
  0.04), the mean post-shock density in 0.25-0.75 R_s against the exact 16, within the uniform
  run's own error plus 1% (measured: uniform 3.9%, graded 3.1%; grading only the outer 15% of the
  radius, which the shock never reaches by t = 0.6, moves the mean by 0.6%: the metric's scatter),
  with 55% of the uniform run's particles. The uniform run at the coarse spacing: 15%.
- Ranks and restarts: the 2D plane wave to 0.5 us on 1 and 3 ranks, and on 3 ranks stopped at
  step 100 and restarted, the same particles bit for bit.

usage: test_graded_spacing.py SPALL SOURCE_DIR
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from spalltest import Checks, final_state, noh_density  # noqa: E402

sys.path.insert(0, str(Path(sys.argv[2]) / "tools" / "python"))
import spall  # noqa: E402

SRC = Path(sys.argv[2])
DECKS = SRC / "decks"
Z = np.sqrt(2700.0 * (68.0e9 + 4.0 / 3.0 * 26.0e9))  # the decks' elastic impedance, rho c_L

t = Checks()


def by_position(out):
    """Initial position (to 10 nm) -> id, of OUT's first snapshot."""
    s = spall.Run(out).snapshot(0)
    keys = np.round(s["position"] / 1e-8).astype(np.int64)
    return {tuple(k): int(i) for k, i in zip(keys, s["id"])}


def reflection(graded, uniform):
    """The reflected amplitude over the incident (see the module's docstring)."""
    kg, ku = by_position(graded), by_position(uniform)
    pairs = [(kg[k], ku[k]) for k in kg if k in ku and 0.3e-3 < k[0] * 1e-8 < 3.7e-3]
    gi = np.array([p[0] for p in pairs])
    ui = np.array([p[1] for p in pairs])
    rg, ru = spall.Run(graded), spall.Run(uniform)
    incident = reflected = 0.0
    for k in range(len(rg.times)):
        a, b = rg.snapshot(k), ru.snapshot(k)
        rows = []
        for s, ids in ((a, gi), (b, ui)):
            where = np.empty(int(s["id"].max()) + 1, dtype=np.int64)
            where[s["id"].astype(np.int64)] = np.arange(len(s["id"]))
            rows.append(where[ids])
        sa, sb = a["stress"][rows[0], 0, 0], b["stress"][rows[1], 0, 0]
        va, vb = a["velocity"][rows[0], 0], b["velocity"][rows[1], 0]
        incident = max(incident, np.abs(0.5 * (sa - Z * va)).max())
        reflected = max(reflected, np.abs(0.5 * ((sa - sb) + Z * (va - vb))).max())
    return reflected / incident, len(pairs)


def plane_waves(tmp):
    deck1 = DECKS / "graded_plane_wave_1d.toml"
    # The uniform bar need only outlast the run: its end at 12 mm turns the pulse's front (at 0
    # mm when t = 0) back into the region compared by (24 - 3.7) mm / c_L = 3.3 us > 3 us. A third
    # of the 20 mm bar's particles.
    flat = ["body.bar.grading.ratio=1.0", "body.bar.grading.max_spacing=1.0e-5",
            'body.bar.shape={type="box", min=[0.0], max=[0.012]}']
    ratios = (1.02, 1.05, 1.1, 1.2)
    done = t.run_all([(deck1, tmp / "w1_uniform", flat)] +
                     [(deck1, tmp / f"w1_{r}", [f"body.bar.grading.ratio={r}"]) for r in ratios])
    if not done[0]:
        return
    measured = {}
    for ratio, ok in zip(ratios, done[1:]):
        out = tmp / f"w1_{ratio}"
        if ok:
            measured[ratio], n = reflection(out, tmp / "w1_uniform")
            print(f"     1D ratio {ratio}: reflected {100 * measured[ratio]:.3f}% ({n} particles "
                  f"compared)")
    if len(measured) == 4:
        t.check(measured[1.05] < 0.01,
                f"1D: the default ratio 1.05 reflects {100 * measured[1.05]:.3f}% (< 1%)")
        r = [measured[k] for k in sorted(measured)]
        t.check(all(a < b for a, b in zip(r, r[1:])),
                "1D: the reflection grows with the ratio: " +
                ", ".join(f"{100 * x:.2f}%" for x in r))
    deck2 = DECKS / "graded_plane_wave_2d.toml"
    # Whole: cut at 8.5 mm (heard at 3.7 mm after 2.2 us, past the run's 2 us) the 2D strip's
    # reflection moved from 0.879% to 0.894% (the discrete operator's precursor).
    flat2 = ["body.bar.grading.ratio=1.0", "body.bar.grading.max_spacing=4.0e-5"]
    if t.run(deck2, tmp / "w2_uniform", *flat2, ranks=2) and t.run(deck2, tmp / "w2", ranks=2):
        r2, n = reflection(tmp / "w2", tmp / "w2_uniform")
        t.check(r2 < 0.01, f"2D strip: ratio 1.05 reflects {100 * r2:.3f}% (< 1%; {n} particles)")


REST = """
[run]
title = "A graded block at rest"
dimension = 2
geometry = "rz"
end_time = 1.0e-5
max_steps = 1000

[[material]]
name = "steel"
density = 7850.0
eos = { type = "mie_gruneisen", c0 = 4570.0, s = 1.49, gamma0 = 1.93 }
strength = { type = "von_mises", shear_modulus = 77.0e9, yield_stress = 1.0e9 }

[[body]]
name = "block"
material = "steel"
shape = { type = "box", min = [0.0, -0.02], max = [0.03, 0.0] }
spacing = 2.5e-4
grading = { within = 3.0e-3, max_spacing = 2.0e-3, line = { point = [0.0, 0.0], direction = [0.0, 1.0] } }
@PRESSURE@
[output]
directory = "out"
every_steps = 1000
"""
CONFINED = """initial_pressure = 1.0e8

[[boundary]]
type = "pressure"
body = "block"
pressure = [[0.0, 1.0e8]]
"""


def at_rest(tmp):
    cases = (("free", ""), ("under 100 MPa", CONFINED))
    for _, extra in cases:
        (tmp / f"rest_{len(extra)}.toml").write_text(REST.replace("@PRESSURE@", extra))
    done = t.run_all([(tmp / f"rest_{len(extra)}.toml", tmp / f"rest_{len(extra)}")
                      for _, extra in cases])
    for (label, extra), ok in zip(cases, done):
        out = tmp / f"rest_{len(extra)}"
        if not ok:
            continue
        s, time = final_state(out)
        peak = np.linalg.norm(s["velocity"], axis=1).max() / s["sound_speed"].min()
        n = len(s["id"])
        t.check(peak < 1e-6, f"rz block at rest, {label}: peak speed {peak:.2e} of the sound "
                             f"speed after 1000 steps (< 1e-6; {n} particles, t = {time:.3g} s)")


def noh(tmp):
    deck = DECKS / "noh_2d.toml"
    common = ["run.resolution=0.5", "output.every=0.6"]
    graded = "body.gas.grading={within = 0.5, ratio = 1.05, max_spacing = 0.04, point = [0.0, 0.0]}"
    if not (t.run(deck, tmp / "noh_uniform", *common, ranks=2) and
            t.run(deck, tmp / "noh_graded", *common, graded, ranks=2)):
        return
    (ru, nu), (rg, ng) = noh_density(tmp / "noh_uniform"), noh_density(tmp / "noh_graded")
    eu, eg = abs(ru / 16.0 - 1.0), abs(rg / 16.0 - 1.0)
    t.check(eg <= eu + 0.01,
            f"Noh 2D graded: post-shock density {rg:.3f} ({100 * eg:.1f}% from 16) within the "
            f"uniform run's {ru:.3f} ({100 * eu:.1f}%) + 1%, with {ng} particles of {nu}")


def ranks_and_restart(tmp):
    deck = DECKS / "graded_plane_wave_2d.toml"
    sets = ["run.end_time=5.0e-7", "output.every=2.5e-7", "checkpoint.every_steps=100"]
    one, three, again = tmp / "r1", tmp / "r3", tmp / "r3_restarted"
    if not (t.run(deck, one, *sets) and t.run(deck, three, *sets, ranks=3)):
        return
    if not (t.run(deck, again, *sets, "run.max_steps=100", ranks=3) and
            t.run(deck, again, *sets, ranks=3, restart="latest")):
        return
    t.same_particles(one, (("3 ranks", three), ("3 ranks, restarted at step 100", again)),
                     "2D graded plane wave, 1 rank")


with tempfile.TemporaryDirectory() as d:
    tmp = Path(d)
    plane_waves(tmp)
    at_rest(tmp)
    noh(tmp)
    ranks_and_restart(tmp)
t.finish()
