#!/usr/bin/python3
"""The cap model (materials/CapPlasticity.hpp) through the single-element driver (`spall element`)
on the materials of tests/verification/element/cap.toml and the tables of make_cap_tables.py:
the tests of Austin (2013), Sec. 4.1.1, with the midpoint kinematics (Eq. 4.8, a step's strain is
the log strain to third order) and 100 substeps a row, every substep written.

- J2 reduction (Sec. 4.1.1.2): cap_j2 in uniaxial strain against the closed form (p = -K ln(lambda),
  the deviator's log-strain increments clipped at 2Y/3) at every substep, and its deviator against
  the von_mises material of j2.toml (same G, Y): tolerance 1e-5 of 2Y/3 (the slope of the reduced
  surface moves Y by < 2e-8 over the path; the kinematics' third-order error is 1e-12).
- Drucker-Prager vertex test (Sec. 4.1.1.3, after Brannon & Leelavanichkul), dilatancy 1 and 0.3:
  the exact solution of perfect linear Drucker-Prager plasticity for the table's strain path (the
  trial stress projected along the fixed return direction onto the line, or the vertex) at every
  substep, within 1e-6 of the 60 MPa confinement; on the surface on every plastic substep; the
  leg along P dwells at its yield point; the legs along N and past the vertex stay on the surface
  and the last ends at the vertex.
- Cap, uniaxial strain (Fig. 4.10a, b; the rock materials): with a fixed cap the stress stays on the
  fixed surface once yielding and visits the Drucker-Prager line, then the cap; with hardening it
  stays on the moving surface and ends outside the initial one (X out past -400 MPa), and
  cap_position and porosity are the crush curve's (Eqs. 4.5-4.6) of the plastic volumetric strain
  (1e-9 relative).
- Hydrostatic compression (Fig. 4.10c, 4.11): fixed cap: I1 = 3K ln(det F) until crush_p0, then
  dwells at crush_p0 (1e-6 relative); evolving cap: I1 = X(eps_v^p) with I1 = 3K (ln det F -
  eps_v^p) at every substep, porosity on Eq. 4.5's curve of I1 (1e-6 relative).
- Load-unload-dilate-reload (Fig. 4.12): the exact hydrostatic path (elastic slope 3K, crush curve,
  dilation at the vertex I1 = peak_i1, re-yield at the retracted cap) at every substep.
- Pore fluid (Fig. 4.13): the saturated sandstone's effective stress is the dry one's, its pore
  pressure is -K_f ln(phi V / phi0 V0) (1e-6 relative), its total pressure is higher at every
  compressed substep, and at equal total pressure it has compacted less (higher porosity).
- Frame indifference (Sec. 4.1.1.1): the sandstone's uniaxial path with a superimposed 360-degree
  rotation; the unrotated stress equals the still element's within 1e-3 of the largest stress.
- Bad decks: an eos or damage given with a cap material: exit 2 at the key.
Plots (PNG, like Austin's figures) go to ./cap_element_plots.

usage: test_cap_element.py SPALL SOURCE_DIR
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
ELEMENT = SRC / "tests" / "verification" / "element"
DECK = ELEMENT / "cap.toml"
PLOTS = Path.cwd() / "cap_element_plots"
K, G, PEAK, FS, CR = 15.7e9, 15.0e9, 20.99e6, 0.435438, 6.0
P0, P1, P3 = -30.0e6, 5.9e-11, 0.189
KF = 2.2e9
UNIT = np.array([2.0, -1.0, -1.0]) / math.sqrt(6.0)
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def drive(material, table, out, *options, deck=DECK, expect=0):
    cmd = [SPALL, "element", str(deck), "--material", material, "--table", str(table),
           "--output", str(out), "--kinematics", "midpoint", "--every-substep", *options]
    p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    if p.returncode != expect:
        check(False, f"{' '.join(cmd[1:])}: exit {p.returncode}, expected {expect}\n{p.stderr}")
    if expect != 0 or not Path(out).exists():
        return p
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def invariants(r):
    """I1 (effective: the pore pressure added back), signed q along UNIT, and q = sqrt(J2)."""
    s = np.stack([r["sxx"], r["syy"], r["szz"]], axis=1)
    pf = r.get("pore_pressure", 0.0)
    I1 = s.sum(axis=1) + 3.0 * pf
    dev = s - s.mean(axis=1, keepdims=True)
    qs = dev @ UNIT / math.sqrt(2.0)
    q = np.sqrt(0.5 * ((r["sxx"] - r["syy"]) ** 2 + (r["syy"] - r["szz"]) ** 2 +
                       (r["szz"] - r["sxx"]) ** 2) / 3.0 + r["sxy"] ** 2 + r["syz"] ** 2 +
                r["sxz"] ** 2)
    return I1, qs, q


def strains(r):
    logs = np.log(np.stack([r["F11"], r["F22"], r["F33"]], axis=1))
    ev = logs.sum(axis=1)
    return ev, (logs - ev[:, None] / 3.0) @ UNIT


def crush_eps(X):
    return np.where(X < P0, P3 * np.expm1(P1 * (X - P0)), P1 * P3 * (X - P0))


def cap_X(eps, p0=P0):
    return np.minimum(np.where(eps < 0, p0 + np.log1p(np.maximum(eps / P3, -1 + 1e-300)) / P1,
                               p0 + eps / (P1 * P3)), PEAK)


def radius(I1, X, fs=FS):
    """F(I1, X) = Ff Fc: sqrt(J2) on the surface."""
    kappa = (X + CR * fs * PEAK) / (1.0 + CR * fs)
    u = np.clip((kappa - I1) / (kappa - X), 0.0, 1.0)
    Fc = np.where(I1 >= kappa, 1.0, np.sqrt(np.maximum(0.0, 1.0 - u * u)))
    return fs * (PEAK - I1) * Fc, kappa


def hydrostatic_reference(ev, hardening=True):
    """The exact hydrostatic path: elastic, crush on the cap tip, or dilation at the vertex."""
    eps, out = 0.0, []
    for e in ev:
        I1 = 3 * K * (e - eps)
        X = cap_X(np.array(eps)) if hardening else P0
        if I1 > PEAK:  # the vertex: the excess is plastic dilation
            eps = e - PEAK / (3 * K)
        elif I1 < X:  # the tip: I1 = X(eps), I1 = 3K (e - eps)
            if not hardening:
                eps = e - P0 / (3 * K)
            else:
                lo, hi = -P3 * (1 - 1e-15), eps
                for _ in range(200):
                    m = 0.5 * (lo + hi)
                    if 3 * K * (e - m) - cap_X(np.array(m)) > 0:
                        lo = m
                    else:
                        hi = m
                eps = 0.5 * (lo + hi)
        out.append((3 * K * (e - eps), eps))
    return np.array(out)


def plot(name, draw):
    save_plot(PLOTS, name, draw)


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)

    # ---- J2 reduction --------------------------------------------------------------------
    Kj, Gj, Y = 68.0e9, 26.0e9, 300.0e6
    CAP = 2.0 * Y / 3.0
    r = drive("cap_j2", ELEMENT / "uniaxial_strain.ftable", tmp / "j2.csv")
    vm = drive("j2", ELEMENT / "uniaxial_strain.ftable", tmp / "vm.csv", deck=ELEMENT / "j2.toml")
    if isinstance(r, dict) and isinstance(vm, dict):
        lam = r["F11"]
        s = np.zeros_like(lam)
        for k in range(1, len(lam)):
            s[k] = np.clip(s[k - 1] + 4.0 / 3.0 * Gj * np.log(lam[k] / lam[k - 1]), -CAP, CAP)
        p = -Kj * np.log(lam)
        worst = max(np.max(np.abs(r["sxx"] - (-p + s))), np.max(np.abs(r["syy"] - (-p - 0.5 * s))),
                    np.max(np.abs(r["szz"] - (-p - 0.5 * s))))
        dev = lambda t: t["sxx"] + t["pressure"]
        versus = np.max(np.abs(dev(r) - dev(vm)))
        yielded = int(np.sum(np.abs(np.abs(s) - CAP) < 1.0))
        check(worst < 1e-5 * CAP and versus < 1e-5 * CAP and yielded > 50,
              f"J2 reduction, uniaxial strain: worst |sigma - closed form| {worst:.3g} Pa, deviator "
              f"vs von_mises {versus:.3g} Pa (< {1e-5 * CAP:.3g}); {yielded} substeps yielded")
        plot("j2_uniaxial_strain", lambda ax: (
            ax.plot(np.log(lam), r["sxx"] / 1e6, label="cap reduced to J2"),
            ax.plot(np.log(lam), (-p + s) / 1e6, "--", label="closed form"),
            ax.set_xlabel("axial log strain"), ax.set_ylabel("sigma_xx (MPa)"),
            ax.set_title("Uniaxial strain, J2 (Austin 2013, Fig. 4.5)")))

    # ---- Drucker-Prager vertex test ---------------------------------------------------------
    for material, table, dil in (("dp", "dp_vertex.ftable", 1.0),
                                 ("dp_nonassoc", "dp_vertex_nonassoc.ftable", 0.3)):
        r = drive(material, ELEMENT / table, tmp / f"{material}.csv")
        if not isinstance(r, dict):
            continue
        ev, e = strains(r)
        I1, qs, _ = invariants(r)
        ref = np.zeros((len(ev), 2))
        plastic = np.zeros(len(ev), dtype=bool)
        for k in range(1, len(ev)):
            I1t = ref[k - 1, 0] + 3 * K * (ev[k] - ev[k - 1])
            qt = ref[k - 1, 1] + math.sqrt(2.0) * G * (e[k] - e[k - 1])
            Ff = FS * (PEAK - I1t)
            if abs(qt) <= Ff and I1t <= PEAK:
                ref[k] = (I1t, qt)
                continue
            plastic[k] = True
            dl = (abs(qt) - Ff) / (G + 9 * K * dil * FS * FS)
            q = abs(qt) - G * dl
            ref[k] = (PEAK, 0.0) if q <= 0 else (I1t - 9 * K * dil * FS * dl, math.copysign(q, qt))
        tol = 1e-6 * 60e6
        worst = max(np.max(np.abs(I1 - ref[:, 0])), np.max(np.abs(qs - ref[:, 1])))
        off = np.max(np.abs(np.abs(qs[plastic]) - FS * (PEAK - np.minimum(I1[plastic], PEAK))))
        n = (len(ev) - 1) // 5  # substeps a leg (5 legs)
        leg2 = slice(n + n // 2 + 2, 2 * n + 1)
        dwell = max(np.ptp(I1[leg2]), np.ptp(qs[leg2]))
        vertex = abs(I1[-1] - PEAK) + abs(qs[-1])
        legs_yield = [int(plastic[1 + j * n:1 + (j + 1) * n].sum()) for j in range(5)]
        check(worst < tol and off < tol and dwell < tol and vertex < tol and all(legs_yield[1:]),
              f"vertex test, dilatancy {dil}: worst |(I1, q) - exact| {worst:.3g} Pa, off the surface "
              f"{off:.3g}, dwell drift {dwell:.3g}, end off the vertex {vertex:.3g} (< {tol:.3g}); "
              f"plastic substeps by leg {legs_yield}")

        def draw(ax, I1=I1, qs=qs, ref=ref, dil=dil):
            x = np.linspace(-80e6, PEAK, 50)
            ax.plot(x / 1e6, FS * (PEAK - x) / 1e6, "k:", label="yield surface")
            ax.plot(x / 1e6, -FS * (PEAK - x) / 1e6, "k:")
            ax.plot(I1 / 1e6, qs / 1e6, label="spall element")
            ax.plot(ref[:, 0] / 1e6, ref[:, 1] / 1e6, "--", label="exact")
            ax.set_xlabel("I1 (MPa)"), ax.set_ylabel("signed sqrt(J2) (MPa)")
            ax.set_title(f"Drucker-Prager vertex test, dilatancy {dil} (Austin Fig. 4.9)")
        plot(f"vertex_test_{material}", draw)

    # ---- cap in uniaxial strain: fixed and evolving -------------------------------------------
    for material, hardening in (("rock_fixed", False), ("rock", True)):
        r = drive(material, ELEMENT / "uniaxial_strain_cap.ftable", tmp / f"u_{material}.csv")
        if not isinstance(r, dict):
            continue
        I1, _, q = invariants(r)
        X = r["cap_position"]
        F, kappa = radius(I1, X, 0.25)
        loading = np.arange(len(I1)) <= 4000  # F11 decreasing
        yielded = loading & (np.cumsum(r["plastic_strain"] > 0) > 0)
        off = np.max(np.abs(q[yielded] - F[yielded])) / 0.25 / (PEAK + 300e6)
        on_dp, on_cap = int(np.sum(yielded & (I1 >= kappa))), int(np.sum(yielded & (I1 < kappa)))
        message = (f"cap, uniaxial strain ({material}): on the surface within {off:.2g} of its "
                   f"size over {yielded.sum()} yielded loading substeps ({on_dp} on the "
                   f"Drucker-Prager line, {on_cap} on the cap)")
        ok = off < 1e-9 and on_cap > 100 and on_dp > 100
        if hardening:
            curve = np.max(np.abs(X - cap_X(r["plastic_volumetric_strain"], -300e6)) / np.abs(X))
            phi = np.max(np.abs(r["porosity"] + np.expm1(-(P3 + r["plastic_volumetric_strain"]))))
            # Fig. 4.10b: the stress leaves the initial surface, staying on the expanding one.
            end = 4000
            outside = I1[end] < X[0] or q[end] > radius(I1[end], X[0], 0.25)[0]
            ok = ok and curve < 1e-9 and phi < 1e-12 and outside and X[end] < -400e6
            message += (f"; the stress ends outside the initial surface, X out to {X[end]:.3g}; X "
                        f"and phi on the crush curve within {curve:.2g} and {phi:.2g}")
        else:
            ok = ok and np.all(X == -300e6)
        check(ok, message)

        def draw(ax, I1=I1, q=q, X=X, material=material):
            for Xs, style in ((X[0], "k:"), (X[4000], "k--")) if hardening else ((X[0], "k:"),):
                x = np.linspace(Xs, PEAK, 400)
                ax.plot(x / 1e6, radius(x, Xs, 0.25)[0] / 1e6, style,
                        label=f"surface, X = {Xs / 1e6:.0f} MPa")
            ax.plot(I1 / 1e6, q / 1e6, label="stress path")
            ax.set_xlabel("I1 (MPa)"), ax.set_ylabel("sqrt(J2) (MPa)")
            ax.set_title(f"Uniaxial strain, {material} (Austin Fig. 4.10)")
        plot(f"uniaxial_strain_{material}", draw)

    # ---- hydrostatic: fixed cap, crush curve, cycle, fluid --------------------------------------
    fixed = drive("sandstone_fixed", ELEMENT / "hydrostatic_crush.ftable", tmp / "hf.csv")
    dry = drive("sandstone", ELEMENT / "hydrostatic_crush.ftable", tmp / "hd.csv")
    wet = drive("sandstone_wet", ELEMENT / "hydrostatic_crush.ftable", tmp / "hw.csv")
    cycle = drive("sandstone", ELEMENT / "hydrostatic_cycle.ftable", tmp / "hc.csv")
    if all(isinstance(x, dict) for x in (fixed, dry, wet, cycle)):
        ev = strains(fixed)[0]
        I1 = invariants(fixed)[0]
        ref = np.maximum(3 * K * ev, P0)
        worst = np.max(np.abs(I1 - ref)) / abs(P0)
        dwell = int(np.sum(ref == P0))
        check(worst < 1e-6 and dwell > 1000 and np.max(invariants(fixed)[2]) < 1.0,
              f"hydrostatic, fixed cap: I1 within {worst:.2g} of min(3K ln det F, crush_p0) "
              f"(relative), {dwell} substeps dwelling at crush_p0, shear-free")
        ev = strains(dry)[0]
        I1 = invariants(dry)[0]
        ref = hydrostatic_reference(ev)
        worst = np.max(np.abs(I1 - ref[:, 0]) / np.maximum(np.abs(ref[:, 0]), abs(P0)))
        crushed = I1 < P0
        eq45 = 1.0 - np.exp(-P3 * np.exp(P1 * (I1 - P0)))
        phi = np.max(np.abs(dry["porosity"][crushed] - eq45[crushed]))
        check(worst < 1e-6 and phi < 1e-6 and crushed.sum() > 1000,
              f"hydrostatic, evolving cap: I1 within {worst:.2g} of the crush curve's (relative), "
              f"porosity within {phi:.2g} of Eq. 4.5 over {crushed.sum()} crushed substeps")
        plot("porosity_crush_curve", lambda ax: (
            ax.plot(-I1 / 3e6, dry["porosity"], label="spall element"),
            ax.plot(-I1[crushed] / 3e6, eq45[crushed], "--", label="Eq. 4.5"),
            ax.set_xlabel("pressure -I1/3 (MPa)"), ax.set_ylabel("porosity"),
            ax.set_title("Hydrostatic compression, evolving cap (Austin Fig. 4.11)")))

        evc = strains(cycle)[0]
        I1c = invariants(cycle)[0]
        refc = hydrostatic_reference(evc)
        worst = np.max(np.abs(I1c - refc[:, 0]) / np.maximum(np.abs(refc[:, 0]), abs(P0)))
        epsc = cycle["plastic_volumetric_strain"]
        n = (len(evc) - 1) // 3
        dilated = epsc[2 * n] - np.min(epsc[n:2 * n + 1])
        at_vertex = int(np.sum(np.abs(I1c - PEAK) < 1e-6 * PEAK))
        phi_up = cycle["porosity"][2 * n] > cycle["porosity"][n]
        reyield = np.argmax((np.arange(len(I1c)) > 2 * n) & (np.diff(epsc, prepend=epsc[0]) < 0))
        X_after = cycle["cap_position"][2 * n]
        check(worst < 1e-6 and abs(dilated - 0.003) < 1e-6 and at_vertex > 10 and phi_up and
              abs(I1c[reyield - 1] - X_after) < 1e-3 * abs(X_after) + 3 * K * abs(evc[1] - evc[0]),
              f"load-unload-dilate-reload: I1 within {worst:.2g} of the exact path (relative); "
              f"{dilated:.6f} of plastic dilation at the vertex ({at_vertex} substeps there), "
              f"porosity up; re-yields at I1 = {I1c[reyield - 1]:.4g} (retracted cap "
              f"{X_after:.4g})")
        plot("hydrostatic_cycle", lambda ax: (
            ax.plot(evc, -I1c / 3e6, label="spall element"),
            ax.plot(evc, -refc[:, 0] / 3e6, "--", label="exact"),
            ax.set_xlabel("volume log strain"), ax.set_ylabel("pressure -I1/3 (MPa)"),
            ax.set_title("Load, unload, dilate, reload (Austin Fig. 4.12)")))

        I1w = invariants(wet)[0]
        same = np.max(np.abs(I1w - I1) / np.maximum(np.abs(I1), abs(P0)))
        phi0 = 1.0 - math.exp(-P3)
        pf = np.maximum(0.0, -KF * (np.log(wet["porosity"] / phi0) + ev))
        pf_err = np.max(np.abs(wet["pore_pressure"] - pf) / np.maximum(pf, 1e6))
        stiffer = bool(np.all(wet["pressure"][1:] > dry["pressure"][1:]))
        # Porosity at equal total pressure: the dry curve interpolated at the wet pressures.
        Pw = wet["pressure"]
        inside = (Pw > 50e6) & (Pw < dry["pressure"].max())
        phi_dry = np.interp(Pw[inside], dry["pressure"], dry["porosity"])
        less = bool(np.all(wet["porosity"][inside] > phi_dry))
        check(same < 1e-9 and pf_err < 1e-6 and stiffer and less and inside.sum() > 1000,
              f"pore fluid: effective stress as dry within {same:.2g}, pore pressure within "
              f"{pf_err:.2g} of -K_f ln(phi V/phi0 V0) (relative), stiffer at every substep, "
              f"less compacted at equal total pressure over {inside.sum()} substeps")
        plot("fluid_trend", lambda ax: (
            ax.plot(-ev, dry["pressure"] / 1e6, label="drained"),
            ax.plot(-ev, wet["pressure"] / 1e6, label="saturated, undrained"),
            ax.plot(-ev, wet["pore_pressure"] / 1e6, ":", label="pore pressure"),
            ax.set_xlabel("volumetric compression -ln det F"), ax.set_ylabel("pressure (MPa)"),
            ax.set_title("Fluid effects (Austin Fig. 4.13)")))

    # ---- frame indifference --------------------------------------------------------------------
    still = drive("sandstone", ELEMENT / "uniaxial_strain_cap.ftable", tmp / "still.csv")
    turning = drive("sandstone", ELEMENT / "uniaxial_strain_cap_rotating.ftable", tmp / "turn.csv")
    if isinstance(still, dict) and isinstance(turning, dict):
        scale = np.max(np.abs(still["sxx"]))
        worst = max(np.max(np.abs(still[c] - turning["u" + c])) for c in
                    ("sxx", "syy", "szz", "sxy", "syz", "sxz"))
        rotated = np.max(np.abs(turning["sxx"] - still["sxx"]))
        phi = np.max(np.abs(still["porosity"] - turning["porosity"]))
        check(worst < 1e-3 * scale and rotated > 0.1 * scale and phi < 1e-6,
              f"superimposed rotation to 360 deg: unrotated stress within {worst:.3g} Pa of the "
              f"still element's (< {1e-3 * scale:.3g}), porosity within {phi:.2g}; the rotated "
              f"stress differs by {rotated:.3g}")

    # ---- bad decks -----------------------------------------------------------------------------
    text = DECK.read_text()
    for key, line in (("eos", 'eos = { type = "linear", bulk_modulus = 1.0e9 }'),
                      ("damage", 'damage = { type = "grady_kipp", weibull_k = 1e30, '
                                 'weibull_m = 9.0 }')):
        bad = tmp / f"bad_{key}.toml"
        bad.write_text(text.replace('name = "dp"\ndensity = 2300.0\n',
                                    f'name = "dp"\ndensity = 2300.0\n{line}\n'))
        p = drive("dp", ELEMENT / "dp_vertex.ftable", tmp / "never.csv", deck=bad, expect=2)
        check(p.returncode == 2 and f"{bad}:" in p.stderr and key in p.stderr and
              not (tmp / "never.csv").exists(), f"{key} with a cap material: {p.stderr.strip()}")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
