#!/usr/bin/python3
"""Faces across a frictionless contact carry no tension (decks/flyer_plate_aluminium_1d.toml).

An aluminium flyer (2 mm, 400 m/s) on a 6 mm aluminium target, von Mises strength, Grady-Kipp
flaws that activate near 60 MPa, 2% of the 3.14 GPa pulse. The impact face is in compression until
the flyer's release arrives, and then the contact parts, which carries no tension: physically
sigma_xx <= 0 near the impact face until the spall's tension arrives there (~2 us).

- Tension: the largest sigma_xx of the target within 0.5 mm of the impact face, and of the flyer
  within 0.2 mm, before 1.8 us, under 3% of the pulse (94 MPa): what remains is SPH's overshoot
  behind a release, measured 0.3-1.9% in 1D and 2.4-2.7% in the 2D strip's touching faces, where
  they part. Before the fix: 53% with five spacings of gap, 16% with one in 2D, 166% touching in
  2D (the frictionless faces stuck and tore apart), and 29 GPa touching in 1D without flaws. The
  cause: a surface particle starts at the deck's density with only its own body in its kernel,
  and the pairs across the contact, counted in its divergence while a gap closed, added the other
  body's share again (the face reached 6.2 GPa with one spacing of gap and 15 GPa with five),
  which the parting read back as tension; and the contact pushed with p, not the normal stress
  (solvers/SphRatesLoop.hpp, contactRule and contactStrain).
- Failure, with the deck's flaws: no target particle within 0.5 mm of the impact face, no flyer
  particle within 0.2 mm, fails; asserted where the tension stays far below the flaws (one spacing
  of gap and touching, 1D; the same with seeds 11 and 23). Before the fix the deck failed target
  particles 30 and 50 um behind the face and a flyer particle 30 um behind its face.
- Analytic for identical materials, at 0.5 us (the pulse 2.8 mm into the target, the flyer's
  release 0.2 us from the contact): the contact and the 50 target rows behind it move at half the
  flyer's speed, u = 200 m/s (symmetry, whatever the EOS and strength), within 0.5% (measured
  0.01-0.33%: a gap leaves an odd-even ripple of a few tenths of a per cent); the plateau's
  -sigma_xx is the elastic-plastic two-wave state at u (an elastic precursor to the HEL, Y/(2G)
  of log strain, then the plastic shock's Rankine-Hugoniot jump on Mie-Gruneisen plus 2Y/3:
  3.1406 GPa, solved below) within 1% (measured 0.02-0.05%); the stress is continuous across a
  contact, so the two face particles' -sigma_xx is within 35% of the plateau's (the face
  particle, stopped by the viscosity while a gap closes, keeps that heat: +26% at one spacing and
  +30% at five, where the divergence across the closing gap made it +97% and +380%; touching,
  +0.1-0.5%).

Cases: the deck (one spacing of gap), five spacings, and bodies that start touching, frictionless
and with `contact = "auto"` (which welds bodies that touch at t = 0), touching at 800 m/s (the
faces and free faces only), in 1D; in 2D a strip six
rows wide, periodic across the impact, touching and frictionless, and one spacing apart with
"auto". Runs without the tension check's flaws have them switched off (weibull_k 1).

- Free faces, with the deck's flaws: no particle within 0.2 mm of the flyer's rear or the
  target's rear fails before 1.8 us (the target spalls inside, 2 mm from its rear, overdriven).
  SPH's one-sided sums at a free face ring into tension as the 3 GPa pulse reflects there; with
  the plain kernel gradient the flyer's two outermost rows failed at 0.4 us touching (and three
  rows of both rears at 800 m/s), the target's outermost at 1.12 us. The corrected gradient,
  exact for a linear field where the support is cut, is the default with flaws
  (solver.velocity_gradient; io/Deck.cpp), and keeps them whole.

usage: test_contact_faces.py SPALL SOURCE_DIR
"""
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from spalltest import Checks  # noqa: E402

SRC = Path(sys.argv[2])
DECK = SRC / "decks" / "flyer_plate_aluminium_1d.toml"
U = 200.0  # the contact's speed: half the flyer's 400 m/s (identical materials)
# The deck's aluminium: Mie-Gruneisen (Lam et al.'s form, materials/Eos.hpp) and von Mises.
RHO0, C0, S, GAMMA0, G, Y = 2703.0, 5350.0, 1.34, 2.0, 26.0e9, 0.29e9

t = Checks()


def snapshots(out):
    for s in sorted((out / "snapshots").glob("snap_*.h5")):
        with h5py.File(s, "r") as f:
            g = f["particles"]
            yield float(f.attrs["time"]), {k: g[k][()] for k in
                                            ("id", "position", "damage", "body", "stress",
                                             "velocity")}


def pressure(rho, e):
    a0 = RHO0 * C0 * C0
    b0, c0 = a0 * (1.0 + 2.0 * (S - 1.0)), a0 * (2.0 * (S - 1.0) + 3.0 * (S - 1.0) ** 2)
    eta = rho / RHO0 - 1.0
    return eta * (a0 + eta * (b0 + eta * c0)) * (1.0 - 0.5 * GAMMA0 * eta / (1.0 + eta)) \
        + GAMMA0 * RHO0 * e


def two_wave_stress(u):
    """-sigma_xx behind an elastic precursor and a plastic shock that bring the material to u."""
    # The precursor: uniaxial elastic strain to |s_xx| = 2Y/3 at ln(rho/rho0) = Y/(2G), e by the
    # work sum sigma dV along it, its speed by the Rayleigh line (O(strain^2) from the ramp).
    n, e, sig = 2000, 0.0, 0.0
    for k in range(1, n + 1):
        r0, r1 = (RHO0 * np.exp(Y / (2.0 * G) * kk / n) for kk in (k - 1, k))
        s1 = 4.0 / 3.0 * G * np.log(r1 / RHO0)
        e += 0.5 * (sig + pressure(r1, e) + s1) * (1.0 / r0 - 1.0 / r1)
        sig = pressure(r1, e) + s1
    VH = np.exp(-Y / (2.0 * G)) / RHO0
    uH = np.sqrt(sig * (1.0 / RHO0 - VH))
    eH, sH = e, sig

    def jump(rho):  # Rankine-Hugoniot from the HEL state to rho: (u, sigma)
        e = eH
        for _ in range(60):
            sig = pressure(rho, e) + 2.0 * Y / 3.0
            e = eH + 0.5 * (sig + sH) * (VH - 1.0 / rho)
        return uH + np.sqrt((sig - sH) * (VH - 1.0 / rho)), sig

    lo, hi = 1.0001 / VH, 1.2 / VH
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if jump(mid)[0] < u else (lo, mid)
    return jump(0.5 * (lo + hi))[1]


def deck_2d(tmp):
    """The deck as a 2D strip, 6 rows of 20 um across, periodic across the impact."""
    s = DECK.read_text()
    for a, b in (("dimension = 1", "dimension = 2"),
                 ("min = [-0.00201], max = [-0.00001]", "min = [-0.002, 0.0], max = [0.0, 1.2e-4]"),
                 ("min = [0.0], max = [0.006]", "min = [0.0, 0.0], max = [0.006, 1.2e-4]"),
                 ("spacing = 1.0e-5", "spacing = 2.0e-5"),
                 ("velocity = [400.0]", "velocity = [400.0, 0.0]"),
                 ("velocity = [0.0]", "velocity = [0.0, 0.0]"),
                 # the flaws of (20 um)^3 activating at the 1D deck's strain: k / 2^3
                 ("weibull_k = 5.0e40", "weibull_k = 6.25e39"),
                 ("end_time = 2.5e-6", "end_time = 1.8e-6"),
                 ('contact = "frictionless"', 'contact = "auto"'),
                 ("[output]", '[[boundary]]\ntype = "periodic"\naxis = 1\nmin = 0.0\n'
                              'max = 1.2e-4\n\n[output]')):
        assert a in s, a
        s = s.replace(a, b)
    path = tmp / "flyer_plate_2d.toml"
    path.write_text(s)
    return path


SIGMA = two_wave_stress(U)
TOUCHING = ["body.flyer.shape.min=[-0.002]", "body.flyer.shape.max=[0.0]"]
GAP5 = ["body.flyer.shape.min=[-0.00205]", "body.flyer.shape.max=[-0.00005]"]
NO_FLAWS = ["material.aluminium.damage.weibull_k=1.0"]  # activation strain ~60: none fails
# label, 2D?, --set, assert no failure near the faces (with the deck's flaws), plateau checks
CASES = [("one spacing of gap (the deck)", False, [], True, True),
         ("five spacings of gap", False, GAP5, False, True),
         ("touching, frictionless", False, TOUCHING, True, True),
         ("touching, contact auto (welded: they touch at t = 0)", False,
          TOUCHING + ["solver.contact=auto"], True, True),
         ("touching at 800 m/s (6.5 GPa)", False, TOUCHING + ["body.flyer.velocity=[800.0]"], True,
          False),
         ("2D strip, touching, frictionless", True, ["solver.contact=frictionless"], False, False),
         ("2D strip, one spacing of gap, contact auto", True,
          ["body.flyer.shape.min=[-0.00202, 0.0]", "body.flyer.shape.max=[-0.00002, 1.2e-4]"],
          False, False)]
PULSE = 3.14e9
TENSION = 0.03  # of the pulse: see the docstring


def history(out):
    """x0 and body by id, each particle's first time at damage 1, the 0.5 us snapshot, and the
    largest sigma_xx near each impact face (target within 0.5 mm, flyer within 0.2 mm) before
    1.8 us (later the spall's tension, overdriven without flaws, reaches the face region)."""
    x0 = body = None
    failed_at, at_05, peak = {}, None, {0: (-np.inf, 0, 0), 1: (-np.inf, 0, 0)}
    rears = None
    for time, a in snapshots(out):
        if x0 is None:
            x0, body = dict(zip(a["id"], a["position"][:, 0])), dict(zip(a["id"], a["body"]))
            faces = {0: max(x for i, x in x0.items() if body[i] == 0),
                     1: min(x for i, x in x0.items() if body[i] == 1)}
            rears = {0: min(x for i, x in x0.items() if body[i] == 0),
                     1: max(x for i, x in x0.items() if body[i] == 1)}
        for i in a["id"][a["damage"] >= 1.0]:
            failed_at.setdefault(i, time)
        if abs(time - 5.0e-7) < 1e-9:
            at_05 = a
        if time < 1.8e-6:
            X = np.array([x0[i] for i in a["id"]])
            sxx = a["stress"][:, 0, 0]
            for b, near in ((0, X > faces[0] - 2e-4), (1, X < faces[1] + 5e-4)):
                m = np.flatnonzero((a["body"] == b) & near)
                k = m[np.argmax(sxx[m])]
                if sxx[k] > peak[b][0]:
                    peak[b] = (sxx[k], time, X[k] - faces[b])
    return x0, body, faces, rears, failed_at, at_05, peak


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    for k, (label, two_d, sets, flaws, plateau) in enumerate(CASES):
        deck = deck_2d(tmp) if two_d else DECK
        out = tmp / f"case{k}"
        if not t.run(deck, out, *sets, *([] if flaws else NO_FLAWS), "output.every=2.5e-8",
                     "run.end_time=1.8e-6", ranks=1):
            continue
        x0, body, faces, rears, failed_at, at_05, peak = history(out)
        for b, name, within in ((1, "target", 5e-4), (0, "flyer", 2e-4)):
            v, when, dx = peak[b]
            t.check(v < TENSION * PULSE,
                    f"{label}: the {name}'s largest sigma_xx within {within * 1e3:g} mm of the "
                    f"impact face before 1.8 us {v / 1e6:.1f} MPa ({v / PULSE:.1%} of the pulse, "
                    f"< {TENSION:.0%}; at {when * 1e6:.2f} us, {abs(dx) * 1e6:.0f} um from the "
                    "face)")
            if flaws:
                near = sorted((abs(x0[i] - faces[b]), tt) for i, tt in failed_at.items()
                              if body[i] == b and abs(x0[i] - faces[b]) < within)
                t.check(not near,
                        f"{label}: no {name} particle failed within {within * 1e3:g} mm of the "
                        f"impact face ({len(near)}: "
                        f"{[(round(x * 1e6), round(tt * 1e6, 2)) for x, tt in near[:6]]} um, us)")
        for b, name in ((0, "flyer"), (1, "target")):
            if not flaws:
                break
            near = sorted((abs(x0[i] - rears[b]), tt) for i, tt in failed_at.items()
                          if body[i] == b and abs(x0[i] - rears[b]) < 2e-4)
            t.check(not near,
                    f"{label}: no {name} particle failed within 0.2 mm of its free rear face "
                    f"({len(near)}: {[(round(x * 1e6), round(tt * 1e6, 2)) for x, tt in near[:6]]}"
                    " um, us)")
        if not plateau:
            continue
        if at_05 is None:
            t.check(False, f"{label}: no snapshot at 0.5 us")
            continue
        a = at_05
        order = np.argsort(a["position"][:, 0])
        tg = order[a["body"][order] == 1]
        fl = order[a["body"][order] == 0]
        v = a["velocity"][:, 0]
        sxx = a["stress"][:, 0, 0]
        plateau_v = v[tg[:50]]
        plateau_s = float(np.median(-sxx[tg[10:60]]))
        contact = [fl[-1], tg[0]]
        worst_v = max(abs(float(x) / U - 1.0) for x in list(plateau_v) + [v[fl[-1]]])
        t.check(worst_v < 0.005,
                f"{label}: at 0.5 us the contact and the 50 target rows behind it at "
                f"{np.min(plateau_v):.2f}-{np.max(plateau_v):.2f} m/s, worst {worst_v:.2%} from "
                f"u = 200 m/s (< 0.5%)")
        t.check(abs(plateau_s / SIGMA - 1.0) < 0.01,
                f"{label}: the plateau's -sigma_xx {plateau_s / 1e9:.4f} GPa, the two-wave "
                f"state's {SIGMA / 1e9:.4f} ({plateau_s / SIGMA - 1.0:+.2%}, within 1%)")
        worst_s = max(abs(-sxx[f] / plateau_s - 1.0) for f in contact)
        t.check(worst_s < 0.35,
                f"{label}: the face particles' -sigma_xx {-sxx[contact[0]] / 1e9:.3f} / "
                f"{-sxx[contact[1]] / 1e9:.3f} GPa against the plateau's {plateau_s / 1e9:.3f} "
                f"({worst_s:.1%}, < 35%)")

t.finish()
