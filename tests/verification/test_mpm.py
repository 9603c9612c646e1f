#!/usr/bin/python3
"""The material point method (solver.method = "mpm") against exact solutions and conservation:

- decks/vibrating_bar_mpm_1d.toml (Buzzi et al. 2008): the first mode of a fixed-free bar keeps
  its period T = 10 within 1% and its centre-of-mass velocity amplitude 2 v0 / pi within 2%
  after five periods (the issue's bounds); the period error falls with the cell size at an
  observed order of at least 1.5 for GIMP (uGIMP, the default; second order expected, measured
  1.6-1.9 here: its boxes, kept as made, do not tile the strained bar) and 1.8 for cpGIMP, whose
  boxes follow the strain (measured 1.97 over 50-200 cells; the same bounds on the period and
  amplitude).
- decks/two_disks_mpm_2d.toml (Sulsky et al. 1994): momentum zero to round-off, total energy
  within 5% at every step (measured: -1.9% at the deepest compression, -0.4% at the end; MUSL
  conserves energy only to the time step's and the grid's truncation, and the disks are 8 cells
  across; bound 2.6x the measured dip), the disks never closer than
  half a spacing (single-field contact stops them a cell apart) and rebound with their speed
  reversed.
- decks/glancing_disks_mpm_2d.toml (frictionless contact, a velocity field per disk; Bardenhagen
  et al. 2000): the disks leave without spin (below 0.1 M v_t R; measured 0.042, while one
  velocity field gives 0.55: the contrast is run and printed), the normal velocity reversed,
  momentum 0 to round-off, energy within 5% at every step (the head-on disks' bound; measured
  -3.1% as they first meet: the contact stops the approach of the nodes it acts on, an
  inelastic collision of a layer a cell thick that the disks' strain takes up over the next
  steps, -0.75% at twice the resolution; +1.2% at the end), the closest points at least a
  quarter spacing apart (measured 0.45: contact acts on nodes, the boxes overlap by a third of a
  cell at most and part again).
- decks/sliding_block_friction_mpm_2d.toml (Coulomb friction between a block and a fixed base,
  Bardenhagen et al. 2000): Coulomb's impulse law while it slides (2% of M v0; measured 1.0%),
  the slide to rest against the quasi-static law (3%; measured 1.1%), sticking at rest (its
  centre within 5 um; measured 2.3), the energy less the load's work within 3% with the
  friction's work booked as heat (measured 2.3%; without it 96% vanishes). The same block on a
  rigid wall with friction (boundary.friction) instead of the base: 1%, 2%, 4 um and 1%
  (measured 0.28%, 0.7%, 1.8 um, 0.43%).
- Austin's steel billet with zero-stress erosion (MPM, run.resolution 0.5): a failed point,
  which carries no stress, does not set the step (the smallest at least 0.3 of the first;
  measured 0.67, against 0.075 when its sound speed counted).

- decks/stretching_bar_mpm_2d.toml (a bar stretched at ten times its wave speed, uniaxial strain,
  to lambda = 3): in the core the release waves have not reached, the exact homogeneous stress
  sigma_xx = K (1 - 1/lambda) + 4/3 mu ln lambda. CPDI with APIC (the deck's): the median point
  within 0.5% and every point within 1% (measured 0.19% and 0.27%), sigma_yy (= K (1 - 1/lambda)
  - 2/3 mu ln lambda) within 1% everywhere (measured 0.44%, first order in the time step: 0.22%
  at twice the resolution), the density within 0.1% / 1% (0.014% / 0.45%). FLIP reported for
  contrast: the few points at the bar's centre, which stay put on the grid, ring in its
  null-space mode (sigma_xx 2.5%, density 3.8%). cpGIMP, whose boxes follow the stretch up to
  half a cell (lambda 2) and part beyond: worst sigma_xx error within 10% (measured 7.5%,
  density 11%). uGIMP (`gimp`) for contrast, asserted: its fixed boxes lose the points' contact as they
  part 1.5 cells: worst sigma_xx error 36%, density 59% (points bunch); the test asserts its
  worst beyond 10%, so the deck keeps showing what CPDI is for.
  A probe on a core point samples its domain by component (r_1,x = 3 l_p within 1%), and a
  sheared, strengthless variant tells R(x, y) from R(y, x) (0.4 l_p against 0).
- decks/stretching_bar_damage_mpm_2d.toml (the bar plastic, von Mises, with Johnson-Cook damage,
  stretched to failure): over the core |X| < 0.5, D and eps_p on their closed forms until
  failure within 2% of their values at failure (measured 0.83%, 0.50%), every point failed
  once the closed form's D passes 1.02 (lambda_f = 1.9125), and after failure what each erosion
  option carries: zero_stress and no_tension nothing (exactly), no_shear the hydrostatic
  K (1 - 1/lambda), none the intact stress (within 1%, measured 0.3%); zero_stress freezes eps_p
  at its failure value 0.3656 (within 2%, measured 0.46%). Restarted before failure on 3 ranks:
  the state after failure bit for bit.
- The vibrating bar with CPDI: the same bounds, and the period error's order at least 1.5
  (measured 2.06). With APIC (GIMP) the same bounds at 50 cells.

Long (third argument "long"): the 4340 Taylor bar in rz against the 3D run, both MPM at the
shipped resolution: length and face within 2% of each other (the penetration issue's bound for
rz against 3D; measured 0.01% and 0.05%: rz MPM is 3D MPM in this scene).

usage: test_mpm.py SPALL SOURCE_DIR [long]
"""
import importlib.machinery
import importlib.util
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from spalltest import Checks  # noqa: E402

SRC = Path(sys.argv[2])
LONG = len(sys.argv) > 3 and sys.argv[3] == "long"
t = Checks()
T_EXACT, V_CM = 10.0, 2 * 0.1 / np.pi  # the bar's period and v_cm amplitude (deck header)


def history(out):
    return np.genfromtxt(out / "history.csv", delimiter=",", names=True)


def bar_errors(out):
    """Period (from v_cm's zero crossings, linear between rows) and the amplitude of v_cm in the
    fifth period, relative to the exact ones."""
    h = history(out)
    time, v = h["time"], h["momentum_x"] / h["mass"]
    s = np.nonzero(v[:-1] * v[1:] < 0)[0]
    zeros = time[s] - v[s] * (time[s + 1] - time[s]) / (v[s + 1] - v[s])
    period = 2 * np.mean(np.diff(zeros))
    amplitude = np.max(np.abs(v[time >= 4 * T_EXACT]))
    return period / T_EXACT - 1, amplitude / V_CM - 1


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    bar = SRC / "decks/vibrating_bar_mpm_1d.toml"
    every = "output.history_every_steps=1"
    errors = {}
    for res in (1, 2, 4):
        out = tmp / f"bar{res}"
        if t.run(bar, out, f"run.resolution={res}", every):
            errors[res] = bar_errors(out)
            print(f"     resolution {res}: period {errors[res][0]:+.2e}, amplitude "
                  f"{errors[res][1]:+.2e}")
    if 1 in errors:
        dT, dA = errors[1]
        t.check(abs(dT) < 0.01, f"vibrating bar (GIMP, 50 cells): period within 1% ({dT:+.2e})")
        t.check(abs(dA) < 0.02,
                f"vibrating bar: v_cm amplitude within 2% after five periods ({dA:+.2e})")
    if 1 in errors and 4 in errors:
        order = np.log2(abs(errors[1][0]) / abs(errors[4][0])) / 2
        t.check(order >= 1.5, f"vibrating bar: period error order {order:.2f} (>= 1.5) over 4x "
                              "finer cells")
    # cpGIMP, whose boxes follow the strain and tile the bar (second order), and CPDI: the same
    # bounds at 50 cells, and the period error's order over 4x finer cells.
    for label, shape, least in (("cpGIMP", "cpgimp", 1.8), ("CPDI", "cpdi", 1.5)):
        runs = {}
        for res in (1, 4):
            out = tmp / f"bar_{shape}{res}"
            if t.run(bar, out, f"run.resolution={res}", every, f'solver.mpm.shape="{shape}"'):
                runs[res] = bar_errors(out)
        if len(runs) == 2:
            dT, dA = runs[1]
            t.check(abs(dT) < 0.01 and abs(dA) < 0.02,
                    f"vibrating bar ({label}, 50 cells): period {dT:+.2e} within 1%, amplitude "
                    f"{dA:+.2e} within 2%")
            order = np.log2(abs(runs[1][0]) / abs(runs[4][0])) / 2
            t.check(order >= least,
                    f"vibrating bar ({label}): period error order {order:.2f} (>= {least})")
    # APIC (GIMP): the same bounds at 50 cells (measured period +1.2e-4, amplitude -2.9e-4: it
    # filters what the grid cannot carry, and damps a little more than FLIP's -5.9e-5).
    out = tmp / "bar_apic"
    if t.run(bar, out, every, 'solver.mpm.transfer="apic"'):
        dT, dA = bar_errors(out)
        t.check(abs(dT) < 0.01 and abs(dA) < 0.02,
                f"vibrating bar (APIC, 50 cells): period {dT:+.2e} within 1%, amplitude {dA:+.2e} "
                "within 2%")
    # The tent for contrast (reported, not asserted): its cell-crossing noise.
    out = tmp / "bar_tent"
    if t.run(bar, out, "run.resolution=4", every, 'solver.mpm.shape="linear"'):
        dT, dA = bar_errors(out)
        print(f"     tent at resolution 4: period {dT:+.2e}, amplitude {dA:+.2e}")

    disks = SRC / "decks/two_disks_mpm_2d.toml"
    out = tmp / "disks"
    if t.run(disks, out):
        h = history(out)
        p = np.hypot(h["momentum_x"], h["momentum_y"])
        scale = h["mass"][0] * 0.1 * np.sqrt(2)  # sum of |m v| at the start
        t.check(np.max(p) < 1e-13 * scale,
                f"two disks: momentum 0 to round-off ({np.max(p) / scale:.1e} of sum |m v|)")
        dE = np.max(np.abs(h["total_energy"] / h["total_energy"][0] - 1))
        t.check(dE < 0.05, f"two disks: total energy within 5% at every step ({dE:.2e})")
        closest, v_end = np.inf, None
        for f in sorted((out / "snapshots").glob("snap_*.h5")):
            with h5py.File(f) as s:
                g = s["particles"]
                x, b, v, m = (g[k][()] for k in ("position", "body", "velocity", "mass"))
            A, B = x[b == 0], x[b == 1]
            d = np.sqrt(((A[:, None, :] - B[None, :, :]) ** 2).sum(-1)).min()
            closest = min(closest, d)
            v_end = (m[b == 0, None] * v[b == 0]).sum(0) / m[b == 0].sum()
        t.check(closest > 0.0125, f"two disks: never closer than half a spacing (closest "
                                  f"{closest:.4f} m, spacing 0.025)")
        ratio = -v_end / 0.1
        t.check(bool(np.all((ratio > 0.8) & (ratio <= 1.0))),
                f"two disks: the lower disk rebounds, speed reversed at {ratio[0]:.3f}, "
                f"{ratio[1]:.3f} of its impact speed (0.8-1; the rest rings in the disks)")

    def spin_and_normal(out):
        """The lower disk at the end: its angular momentum about its own centre over M v_t R,
        and its velocity along the line of centres at first contact over the approach speed."""
        last = sorted((out / "snapshots").glob("snap_*.h5"))[-1]
        with h5py.File(last) as s:
            g = s["particles"]
            x, b, v, m = (g[k][()] for k in ("position", "body", "velocity", "mass"))
        x, v, m = x[b == 0], v[b == 0], m[b == 0]
        M = m.sum()
        r = x - (m[:, None] * x).sum(0) / M
        u = v - (m[:, None] * v).sum(0) / M
        spin = (m * (r[:, 0] * u[:, 1] - r[:, 1] * u[:, 0])).sum()
        n = np.array([np.sqrt(0.4**2 - 0.18**2), 0.18]) / 0.4  # centres 2 R apart at contact
        vn0 = 0.1 * n[0]
        return spin / (M * 0.1 * n[1] * 0.2), ((m[:, None] * v).sum(0) / M) @ n / vn0

    glancing = SRC / "decks/glancing_disks_mpm_2d.toml"
    out = tmp / "glancing"
    if t.run(glancing, out):
        h = history(out)
        p = np.hypot(h["momentum_x"], h["momentum_y"])
        scale = h["mass"][0] * 0.1
        t.check(np.max(p) < 1e-13 * scale,
                f"glancing disks: momentum 0 to round-off ({np.max(p) / scale:.1e} of sum |m v|)")
        dE = np.max(np.abs(h["total_energy"] / h["total_energy"][0] - 1))
        t.check(dE < 0.05, f"glancing disks: total energy within 5% at every step ({dE:.2e})")
        closest = np.inf
        for f in sorted((out / "snapshots").glob("snap_*.h5")):
            with h5py.File(f) as s:
                x, b = s["particles/position"][()], s["particles/body"][()]
            d = np.sqrt(((x[b == 0][:, None, :] - x[b == 1][None, :, :]) ** 2).sum(-1)).min()
            closest = min(closest, d)
        t.check(closest > 0.25 * 0.025, f"glancing disks: closest points {closest / 0.025:.2f} "
                                        "spacings apart (at least 0.25)")
        spin, vn = spin_and_normal(out)
        t.check(abs(spin) < 0.1, f"glancing disks (frictionless): no spin, {spin:+.3f} M v_t R")
        t.check(-1.0 <= vn < -0.5, f"glancing disks: normal velocity reversed at {-vn:.3f} of "
                                   "the approach (0.5-1)")
    out = tmp / "glancing_welded"
    if t.run(glancing, out, 'solver.contact="welded"'):
        spin, vn = spin_and_normal(out)
        print(f"     one velocity field (welded) for contrast: spin {spin:+.3f} M v_t R, normal "
              f"velocity {-vn:.3f} of the approach")

    # Coulomb friction (the sliding block's header): while the block slides, the base's
    # tangential impulse is mu times its normal one, dP_x = -mu (dP_y + w int P dt) (the normal
    # impulse from the block's own momentum and the load's). 2% of M v0: measured 1.0%, 0.55% at
    # twice the resolution (first order: the interface's nodes where the block's edges only
    # partly cover the support stick or slide less than the rest). The slide to rest against
    # the quasi-static law v = v0 - mu w int P dt / M within 3% (measured 1.1% short: the law
    # takes the normal force as the load, which the block's ringing modulates; 0.3% long at
    # twice the resolution). At rest it sticks: its centre rings within 5 um over the last 15 us
    # (measured 2.3; frictionless it slides on 150 um). The friction's work is heat: the total
    # energy less the load's work within 3% at every step (measured 2.3%, 1.5% at twice the
    # resolution; without the heat 96% of it vanishes).
    mu, w, v0, P0, ramp = 0.3, 0.02, 10.0, 50.0e6, 5.0e-6

    def load_impulse(time):  # w int_0^t P dt, the load ramping to P0 over `ramp`
        return w * np.where(time < ramp, 0.5 * P0 * time**2 / ramp, P0 * (time - 0.5 * ramp))

    def sliding_checks(out, what, bounds):
        """The block (the deck's last body) against Coulomb's law; bounds: the impulse law's
        (of M v0), the slide's (relative), the ringing at rest (m) and the energy's."""
        h = history(out)

        def block(f):  # time, the block's mass and its centre
            with h5py.File(f) as s:
                g = s["particles"]
                b, m, x = g["body"][()], g["mass"][()], g["position"][()]
                b = b == b.max()
                return s.attrs["time"], m[b].sum(), (m[b, None] * x[b]).sum(0) / m[b].sum()

        snaps = sorted((out / "snapshots").glob("snap_*.h5"))
        _, M, x0 = block(snaps[0])
        tq = np.linspace(0.0, 4.0e-5, 400001)
        vq = np.maximum(v0 - mu * load_impulse(tq) / M, 0.0)
        t_stop, s_stop = tq[np.argmax(vq <= 0.0)], np.trapz(vq, tq)
        time = h["time"]
        dpx = h["momentum_x"] - h["momentum_x"][0]
        dpy = h["momentum_y"] - h["momentum_y"][0]
        coulomb = np.abs(dpx + mu * (dpy + load_impulse(time)))[time < 0.9 * t_stop].max()
        t.check(coulomb < bounds[0] * M * v0,
                f"{what}: Coulomb's impulse law while it slides to {coulomb / (M * v0):.4f} of "
                f"M v0 ({bounds[0]:g})")
        rest = [block(f)[2][0] - x0[0] for f in snaps if block(f)[0] >= t_stop + 4.0e-6]
        t.check(abs(rest[0] / s_stop - 1) < bounds[1],
                f"{what}: slides {rest[0] * 1e6:.1f} um to rest, quasi-static law "
                f"{s_stop * 1e6:.1f} um ({rest[0] / s_stop - 1:+.4f}; {bounds[1]:g})")
        t.check(np.ptp(rest) < bounds[2], f"{what}: sticks at rest, its centre within "
                                          f"{np.ptp(rest) * 1e6:.2f} um over the last 15 us "
                                          f"({bounds[2] * 1e6:g})")
        dE = np.abs((h["total_energy"] - h["external_work"]) / h["total_energy"][0] - 1).max()
        t.check(dE < bounds[3], f"{what}: total energy less the load's work within {dE:.4f} at "
                                f"every step ({bounds[3]:g}; the friction's work booked as heat)")

    slide = SRC / "decks/sliding_block_friction_mpm_2d.toml"
    out = tmp / "sliding_block"
    if t.run(slide, out):
        sliding_checks(out, "sliding block", (0.02, 0.03, 5.0e-6, 0.03))
    # ... on a rigid wall with friction instead of the fixed base (boundary.friction): the same
    # law, where the wall's nodes lose up to mu times what the force presses on them. Tighter,
    # as measured: the impulse law to 0.28% of M v0, the slide 0.7% long, 1.8 um of ringing,
    # the energy within 0.43% (a wall has no second field whose slides the grid averages).
    wall = tmp / "sliding_block_wall.toml"
    text = slide.read_text()
    base = text[text.index('[[body]]\nname = "base"'):text.index('[[body]]\nname = "block"')]
    wall.write_text(text.replace(base, "").replace(
        'contact = "friction"\nmpm = { shape = "gimp", friction = 0.3 }',
        'mpm = { shape = "gimp" }').replace(
        '[[boundary]]\ntype = "pressure"', '[[boundary]]\ntype = "rigid_wall"\npoint = [0.0, 0.01]'
        '\nnormal = [0.0, 1.0]\nfriction = 0.3\n\n[[boundary]]\ntype = "pressure"'))
    out = tmp / "sliding_block_wall"
    if t.run(wall, out):
        sliding_checks(out, "block on a wall", (0.01, 0.02, 4.0e-6, 0.01))

    # Zero-stress erosion in penetration: Austin's steel billet (rod_into_steel_rz, both
    # materials eroding to zero stress, his second case) with MPM at run.resolution 0.5. A
    # failed point carries no stress, so nothing resists the grid compressing it: its EOS sound
    # speed must not set the step (it did: on Austin's full-size sandstone target the step fell
    # 40-fold by 21 us, one tungsten point at 96 times its density). Bound: the smallest step at
    # least 0.3 of the first (measured 0.67, 2050 steps; before, 0.075 and 10,290 steps), with
    # failed points in the run (915).
    billet = SRC / "decks/rod_into_steel_rz.toml"
    out = tmp / "billet_zero_stress"
    if t.run(billet, out, "solver.method=mpm", "run.resolution=0.5",
             'material.tungsten_alloy.erosion="zero_stress"', 'material.steel.erosion="zero_stress"'):
        h = history(out)
        dt = h["dt"][1:]
        with h5py.File(sorted((out / "snapshots").glob("snap_*.h5"))[-1]) as s:
            failed = int((s["particles/damage"][()] >= 1.0).sum())
        t.check(failed > 0, f"billet, zero_stress: {failed} points failed (the case bites)")
        t.check(dt.min() > 0.3 * dt[0], f"billet, zero_stress: the smallest step "
                                        f"{dt.min() / dt[0]:.3f} of the first (0.3)")
        d = np.genfromtxt(out / "penetration.csv", delimiter=",", names=True)
        print(f"     billet, zero_stress, MPM at resolution 0.5: {d['depth'].max() * 1e3:.1f} mm "
              f"by {d['time'][-1] * 1e6:.0f} us (Austin's Uintah 52.3 mm)")

    # The stretching bar: the core's stress against the exact homogeneous stretch (deck header).
    stretch = SRC / "decks/stretching_bar_mpm_2d.toml"
    K, mu, lam = 60.0, 30.0, 3.0
    sxx = K * (1 - 1 / lam) + 4 / 3 * mu * np.log(lam)
    syy = K * (1 - 1 / lam) - 2 / 3 * mu * np.log(lam)

    def stretch_errors(out):
        """|relative error| of sigma_xx, sigma_yy and rho at the end, over the points of the core
        |X| < 0.7: the release front has reached |X| = 0.8 (1 - c t), and a margin of two cells
        keeps its numerical spread out."""
        snaps = sorted((out / "snapshots").glob("snap_*.h5"))
        state = []
        for f in (snaps[0], snaps[-1]):
            with h5py.File(f) as s:
                g = s["particles"]
                o = np.argsort(g["id"][()])
                state.append({k: g[k][()][o] for k in ("position", "stress", "density")})
        core = np.abs(state[0]["position"][:, 0]) < 0.7
        end = state[1]
        return (np.abs(end["stress"][core, 0, 0] / sxx - 1),
                np.abs(end["stress"][core, 1, 1] / syy - 1),
                np.abs(end["density"][core] * lam - 1))

    # With CPDI the probe also samples the point's domain (a field GIMP does not have).
    stretch_cpdi = tmp / "stretching_bar_cpdi.toml"
    stretch_cpdi.write_text(stretch.read_text().replace(
        'fields = ["stress_xx", "stress_yy", "density"]',
        'fields = ["stress_xx", "stress_yy", "density", "particle_domain_xx", '
        '"particle_domain_yy", "particle_domain_xy"]'))
    out = tmp / "stretch_cpdi"
    if t.run(stretch_cpdi, out):
        exx, eyy, erho = stretch_errors(out)
        t.check(np.median(exx) < 0.005 and exx.max() < 0.01,
                f"stretching bar (CPDI, APIC, lambda 3): sigma_xx {sxx:.2f}, median error "
                f"{np.median(exx):.2e} (< 0.5%), worst {exx.max():.2e} (< 1%)")
        t.check(eyy.max() < 0.01, f"stretching bar (CPDI): sigma_yy {syy:.2f} within 1% at every "
                                  f"core point ({eyy.max():.2e})")
        # The probe: a core point's domain, r_1 = (lambda l_p, 0), r_2 = (0, l_p), l_p = 0.0125:
        # exact up to the point's velocity gradient (the steps' 1 + dt G / lambda_n telescope to
        # lambda), bound 1% as the core's sigma_xx (measured 0.1%).
        probes = np.genfromtxt(out / "probes.csv", delimiter=",", names=True, dtype=None,
                               encoding="utf-8")
        last = {r["field"]: r["value"] for r in probes if r["time"] == probes["time"].max()}
        t.check(abs(last["particle_domain_xx"] / (3 * 0.0125) - 1) < 0.01
                and abs(last["particle_domain_yy"] / 0.0125 - 1) < 0.01
                and abs(last["particle_domain_xy"]) < 1e-3 * 0.0125,
                f"stretching bar (CPDI): the probed core point's domain r_1,x "
                f"{last['particle_domain_xx']:.5f} (3 l_p = 0.0375), r_2,y "
                f"{last['particle_domain_yy']:.5f} (0.0125), r_2,x {last['particle_domain_xy']:.1e}")
        t.check(np.median(erho) < 0.001 and erho.max() < 0.01,
                f"stretching bar (CPDI, APIC): density rho0/3, median error "
                f"{np.median(erho):.2e} (< 0.1%), worst {erho.max():.2e} (< 1%)")
    # FLIP for contrast (reported): the centre's points ring in its null-space mode.
    out = tmp / "stretch_flip"
    if t.run(stretch, out, 'solver.mpm.transfer="flip"'):
        exx, eyy, erho = stretch_errors(out)
        print(f"     with FLIP: sigma_xx worst {exx.max():.2e}, density worst {erho.max():.2e}")
    # ... sheared as well (v_x += 20 y) and strengthless, so that the stress stays isotropic and
    # the slip walls carry it: still homogeneous, R = (I + t L_0) l_p, the core point's r_2 =
    # (0.4 l_p, l_p) and r_1 = (3 l_p, 0): the probe's particle_domain_xy is R(x, y) = 0.005 and
    # _yx 0 (a transposed component reads them the other way round). Within 5% (the domain
    # follows the grid's L, which a fluid's shear leaves noisier: measured +2%; 0.1% for the
    # unsheared elastic bar).
    sheared = tmp / "stretching_bar_sheared.toml"
    sheared.write_text(stretch_cpdi.read_text().replace(
        "gradient = [[100.0, 0.0], [0.0, 0.0]]", "gradient = [[100.0, 20.0], [0.0, 0.0]]").replace(
        'strength = { type = "elastic", shear_modulus = 30.0 }', "").replace(
        '"particle_domain_xy"]', '"particle_domain_xy", "particle_domain_yx"]'))
    out = tmp / "stretch_sheared"
    if t.run(sheared, out):
        probes = np.genfromtxt(out / "probes.csv", delimiter=",", names=True, dtype=None,
                               encoding="utf-8")
        last = {r["field"]: r["value"] for r in probes if r["time"] == probes["time"].max()}
        xy, yx = last["particle_domain_xy"], last["particle_domain_yx"]
        t.check(abs(xy / 0.005 - 1) < 0.05 and abs(yx) < 1e-3 * 0.0125,
                f"sheared stretching bar (CPDI): probe particle_domain_xy {xy:.6f} (R(x, y) = 0.4 "
                f"l_p = 0.005), particle_domain_yx {yx:.1e} (0)")
    # cpGIMP's boxes follow the stretch to half a cell (lambda 2) and part beyond it; uGIMP's
    # keep their size and part from the start.
    out = tmp / "stretch_cpgimp"
    if t.run(stretch, out, 'solver.mpm.shape="cpgimp"'):
        exx, eyy, erho = stretch_errors(out)
        t.check(exx.max() < 0.1, f"stretching bar with cpGIMP (its boxes follow the stretch to "
                                 f"half a cell): worst sigma_xx error {exx.max():.2e} (< 10%), "
                                 f"density {erho.max():.2e}")
    out = tmp / "stretch_gimp"
    if t.run(stretch, out, 'solver.mpm.shape="gimp"'):
        exx, eyy, erho = stretch_errors(out)
        t.check(exx.max() > 0.1, f"stretching bar with uGIMP, the contrast: its points lose "
                                 f"contact, worst sigma_xx error {exx.max():.2e} (> 10%), density "
                                 f"{erho.max():.2e}")

    # Johnson-Cook damage and erosion on the stretched plastic bar (the deck's header): the core
    # |X| < 0.5 (the release front stays beyond 0.8, and its numerical spread, a few cells per
    # step ahead of it in an explicit grid, beyond 0.6) against the closed form.
    damage_deck = SRC / "decks/stretching_bar_damage_mpm_2d.toml"
    Y, D1, D2, D3 = 6.0, 0.25, 0.5, -0.5
    ln_y = Y / (2 * mu)

    def damage_exact(lam):
        """D(lambda) and eps_p(lambda): the trapezoidal rule on 4000 intervals of ln lambda
        (the integrand is smooth: 1e-7 of D)."""
        if np.log(lam) <= ln_y:
            return 0.0, 0.0
        x = np.linspace(ln_y, np.log(lam), 4001)
        f = (2 / 3) / (D1 + D2 * np.exp(D3 * K * (1 - np.exp(-x)) / Y))
        return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x))), 2 / 3 * (np.log(lam) - ln_y)

    def after_failure(erosion, lam):
        """What a failed core point carries: (sigma_xx, sigma_yy)."""
        hydro = K * (1 - 1 / lam)
        return {"zero_stress": (0.0, 0.0), "no_tension": (0.0, 0.0), "no_shear": (hydro, hydro),
                "none": (hydro + 2 * Y / 3, hydro - Y / 3)}[erosion]

    for erosion in ("zero_stress", "no_tension", "no_shear", "none"):
        out = tmp / f"damage_{erosion}"
        if not t.run(damage_deck, out, f'material.bar.erosion="{erosion}"'):
            continue
        snaps = sorted((out / "snapshots").glob("snap_*.h5"))
        err_D = err_eps = err_sigma = 0.0
        unfailed, eps_frozen, after = [], [], 0
        for k, path in enumerate(snaps):
            with h5py.File(path) as f:
                g = f["particles"]
                o = np.argsort(g["id"][()])
                s = {n: g[n][()][o] for n in ("position", "damage", "plastic_strain", "stress")}
                time = float(f.attrs["time"])
            if k == 0:
                core = np.abs(s["position"][:, 0]) < 0.5
            lam = 1 + 100.0 * time
            D_ex, eps_ex = damage_exact(lam)
            if D_ex < 0.98:  # before failure: D and eps_p on the closed form, as fractions of
                # their values at failure (1 and 0.3656): a 2% error is a failure 2% early or
                # late (relative to D itself the yield onset's step dominates the first rows)
                err_D = max(err_D, float(np.abs(s["damage"][core] - D_ex).max()))
                err_eps = max(err_eps,
                              float(np.abs(s["plastic_strain"][core] - eps_ex).max()) / 0.3656)
            elif D_ex > 1.02:  # after: every core point failed, carrying what the option says
                after += 1
                if not np.all(s["damage"][core] == 1.0):
                    unfailed.append(f"{lam:.3f}")
                sxx, syy = after_failure(erosion, lam)
                for comp, exact in (((0, 0), sxx), ((1, 1), syy)):
                    got = s["stress"][core][:, comp[0], comp[1]]
                    err_sigma = max(err_sigma, float(np.abs(got).max()) if exact == 0.0
                                    else float(np.abs(got / exact - 1).max()))
                if erosion == "zero_stress":
                    eps_frozen.append(float(np.abs(s["plastic_strain"][core] / 0.3656 - 1).max()))
        name = f"stretched bar to failure, erosion {erosion}"
        t.check(err_D < 0.02 and err_eps < 0.02,
                f"{name}: D and eps_p within 2% of their values at failure of the closed form "
                f"until then (worst {err_D:.2%}, {err_eps:.2%})")
        t.check(after >= 10 and not unfailed,
                f"{name}: every core point failed once the closed form passed 1.02 (lambda_f "
                f"1.9125){'; not at lambda ' + ', '.join(unfailed) if unfailed else ''}")
        zero = erosion in ("zero_stress", "no_tension")
        t.check(err_sigma == 0.0 if zero else err_sigma < 0.01,
                f"{name}: after failure the stress is " + ("zero exactly" if zero else
                f"{'the hydrostatic' if erosion == 'no_shear' else 'the intact'} one within 1%") +
                f" (worst {err_sigma:.2e})")
        if erosion == "zero_stress":
            t.check(max(eps_frozen) < 0.02, f"{name}: the plastic strain frozen at failure, "
                                            f"0.3656 within 2% ({max(eps_frozen):.2%})")

    # ... and through a restart: to 6 ms (before failure) on 1 rank, then on 3 ranks to 12 ms
    # (past it), against the straight run: every field bit for bit (the damage and the frozen
    # history are checkpointed).
    straight, chain = tmp / "damage_straight", tmp / "damage_chain"
    if (t.run(damage_deck, straight, "run.end_time=0.012")
            and t.run(damage_deck, chain, "run.end_time=0.006")
            and t.run(damage_deck, chain, "run.end_time=0.012", ranks=3, restart="latest")):
        ends = []
        for out in (straight, chain):
            with h5py.File(sorted((out / "snapshots").glob("snap_*.h5"))[-1]) as f:
                g = f["particles"]
                o = np.argsort(g["id"][()])
                ends.append({k: g[k][()][o] for k in g})
        # history.csv's dt is the step taken (the steps cut to land on the 2.5e-4 s snapshot
        # times included): each row's time minus the last, to the rounding of the times.
        hist = np.genfromtxt(straight / "history.csv", delimiter=",", names=True)
        gap = np.abs(np.diff(hist["time"]) - hist["dt"][1:]).max() / hist["dt"].max()
        t.check(gap < 1e-9, f"stretched bar: history.csv's dt is each step's time difference "
                            f"({gap:.1e} of the largest step)")
        differ = [k for k in ends[0] if not np.array_equal(ends[0][k], ends[1][k])]
        t.check(not differ and ends[0]["damage"].max() == 1.0,
                "stretched bar to failure: restarted before failure on 3 ranks, the state after "
                "it bit for bit" + (f" (differ: {differ})" if differ else ""))

    if LONG:
        # tools/taylor's own measure (the rim of the face layer), as for SPH's rz test.
        loader = importlib.machinery.SourceFileLoader("taylor", str(SRC / "tools" / "taylor"))
        tool = importlib.util.module_from_spec(importlib.util.spec_from_loader("taylor", loader))
        loader.exec_module(tool)
        ends = {}
        for geometry in ("rz", "3d"):
            out = tmp / f"taylor_{geometry}"
            if t.run(SRC / f"decks/taylor_bar_4340_{geometry}.toml", out, 'solver.method="mpm"'):
                m = tool.measure(out)
                ends[geometry] = (m["length"], m["diameter"])
        if len(ends) == 2:
            for k, name in enumerate(("length", "face diameter")):
                a, b = ends["rz"][k], ends["3d"][k]
                t.check(abs(a / b - 1) < 0.02, f"4340 Taylor bar (MPM): rz {name} {a * 1e3:.3f} mm "
                                               f"within 2% of 3D {b * 1e3:.3f} mm ({a / b - 1:+.2%})")
t.finish()
