#!/usr/bin/python3
"""Axisymmetric runs (run.geometry = "rz", solvers/Axisymmetric.hpp) against exact solutions, the
conservation laws and the 3D run of the same Taylor bar.

1. A uniform radial stretch v_r = alpha r of an elastic cylinder, periodic along z: until the
   release from its free surface arrives, the interior stays uniform with
   rho = rho0/(1 + alpha t)^2, p = K (rho/rho0 - 1), S_rr = S_tt = (2G/3) ln(1 + alpha t),
   S_zz = -2 S_rr and v_r/r = alpha/(1 + alpha t): the hoop strain rate in the density and the
   stress, and the hoop force, which must balance the summed (sigma_rr, sigma_rz)/r exactly, up to
   the rings next to the axis. With the corrected gradient (exact for linear fields) within 1e-4
   relative (measured 6e-6: the time integration); with the plain one within 1% (measured 0.67%:
   the cubic spline's kernel-sum normalisation at h = 1.5 spacings, the same in plane strain);
   ASPH likewise within 1%.
2. A nearly pressureless ("dust": 0.6 MPa, sound speed 30 m/s against 100 m/s at the rim) cylinder stretched to twice its radius: rho = rho0/4 inside, by
   continuity and by summation of the rings' area masses, within 5% (measured 3.5% and 2.1%: the
   plain gradient's normalisation, and steps of 3% strain, the time step having no strain-rate
   limit; without the hoop rate, or without the ring mass 2 pi r, rho would be rho0/2).
3. A copper rod into an aluminium one, both on the axis, at 600 m/s (strength, two bodies,
   impact, shocks): momentum along z conserved to round-off (the pair terms weighted by
   Rbar/R_i are antisymmetric in the rings' masses; bound 1e-12 of |p_z|), total energy within
   1e-4 (measured 1.3e-5, the time integration's error; the unweighted area-weighted form gained
   30%), and no ring ever at r < 0.
   A space probe averages over the rings' areas: r at r = 2.5 mm within 1e-3, sigma_tt as above.
4. The 4340 Taylor bar in rz (decks/taylor_bar_4340_rz.toml) against the 3D run at the same
   spacing (the 3D deck's header states its measured length and face): within 2% each (the
   penetration issue's bound; measured 0.15% and 0.3%).

usage: test_axisymmetric.py SPALL SOURCE_DIR
"""
import importlib.machinery
import importlib.util
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

import spalltest

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
failures = []


def check(ok, message):
    print(("ok   " if ok else "FAIL ") + message)
    if not ok:
        failures.append(message)


def run(deck_text, out, *sets, ranks=1):
    deck = out.with_suffix(".toml")
    deck.write_text(deck_text)
    launcher, env = spalltest.mpirun(ranks)
    cmd = launcher + [SPALL, "run", str(deck), "--output", str(out), "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, stdin=subprocess.DEVNULL)
    if p.returncode != 0:
        check(False, f"{out.name}: exit {p.returncode}\n{p.stderr[-2000:]}")
        return False
    return True


def last_snapshot(out):
    return sorted((out / "snapshots").glob("snap_*.h5"))[-1]


def stretched_cylinder(material, R, H, alpha, end_time, extra=""):
    """A deck: a cylinder of `material` (its TOML lines, named "m"), radius R and height H, periodic
    along z, given v_r = alpha r, one snapshot at end_time."""
    return f"""
[run]
title = "uniform radial stretch, rz"
dimension = 2
geometry = "rz"
end_time = {end_time!r}
[[material]]
name = "m"
{material}
[[body]]
name = "cylinder"
material = "m"
shape = {{ type = "box", min = [0.0, 0.0], max = [{R!r}, {H!r}] }}
spacing = 2.5e-4
linear_velocity = {{ center = [0.0, 0.0], gradient = [[{alpha!r}, 0.0], [0.0, 0.0]] }}
{extra}
[[boundary]]
type = "periodic"
axis = 1
min = 0.0
max = {H!r}
[output]
directory = "unused"
every = {end_time!r}
fields = ["velocity", "density", "pressure", "stress", "stress_hoop"]
"""


ELASTIC = stretched_cylinder("""density = 2700.0
eos = { type = "linear", bulk_modulus = 70.0e9 }
strength = { type = "elastic", shear_modulus = 26.0e9 }""", 20.0e-3, 4.0e-3, 100.0, 1.0e-6)
# A space probe at r = 2.5 mm, where the rings lie symmetric about it: its kernel average of r is
# 2.5 mm when particles weigh by their area in the r-z plane, 0.7% more by their ring volume.
ELASTIC += """
[[probe]]
name = "p"
position = [2.5e-3, 2.0e-3]
track = "space"
fields = ["position_x", "stress_hoop"]
"""


# MPM takes no periodic boundary: slip walls at both ends hold v_z = 0 just as well.
ELASTIC_WALLS = ELASTIC.replace("""[[boundary]]
type = "periodic"
axis = 1
min = 0.0
max = 0.004""", """[[boundary]]
type = "rigid_wall"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[boundary]]
type = "rigid_wall"
point = [0.0, 0.004]
normal = [0.0, -1.0]""")


def stretch_state(out):
    """The last snapshot of a stretched-cylinder run: radii, the interior mask and each checked
    field's values beside its exact value."""
    alpha, K, G, rho0, R = 100.0, 70.0e9, 26.0e9, 2700.0, 20.0e-3
    with h5py.File(last_snapshot(out)) as f:
        t = float(f.attrs["time"])
        x, v = f["particles/position"][...], f["particles/velocity"][...]
        rho, sigma = f["particles/density"][...], f["particles/stress"][...]
        hoop = f["particles/stress_hoop"][...]
    stretch = 1.0 + alpha * t
    p = K * (stretch ** -2 - 1.0)
    Srr = 2.0 * G / 3.0 * math.log(stretch)
    # The release from r = R(t) travels inward at the longitudinal speed: the interior it has not
    # reached, ten spacings to spare: the front is smeared over a few smoothing lengths, with
    # ringing ahead of it (1e-4 of v_r at 8 spacings before the nominal front).
    cL = math.sqrt((K + 4.0 * G / 3.0) / rho0)
    inside = x[:, 0] < R * stretch - cL * t - 10.0 * 2.5e-4
    exact = {"density": (rho, rho0 / stretch ** 2), "sigma_rr": (sigma[:, 0, 0], Srr - p),
             "sigma_zz": (sigma[:, 1, 1], -2.0 * Srr - p), "sigma_tt": (hoop, Srr - p),
             "v_r/r": (v[:, 0] / x[:, 0], alpha / stretch)}
    return x[:, 0], inside, exact, Srr - p


def elastic(tmp, label, tolerance, *sets):
    out = tmp / f"elastic_{label}"
    if not run(ELASTIC, out, *sets):
        return
    _, inside, exact, sigma_tt = stretch_state(out)
    for name, (got, want) in exact.items():
        err = float(np.max(np.abs(got[inside] - want))) / abs(want)
        check(err < tolerance, f"uniform radial stretch ({label}): {name} within {tolerance:g} of "
                               f"exact in {inside.sum()} interior rings, axis included ({err:.1e})")
    probes = np.genfromtxt(out / "probes.csv", delimiter=",", names=True, dtype=None, encoding=None)
    last = probes[probes["time"] == probes["time"].max()]
    for field, want, tol in (("position_x", 2.5e-3, 1e-3), ("stress_hoop", sigma_tt, tolerance)):
        got = float(last["value"][last["field"] == field][0])
        err = abs(got / want - 1.0)
        check(err < tol, f"uniform radial stretch ({label}): space probe {field} within {tol:g} "
                         f"({err:.1e})")


# c = 30 m/s: steps of 3% strain (the time step has no strain-rate limit); the release from the
# rim reaches 3 mm in, outside the rings checked.
DUST = stretched_cylinder("""density = 1000.0
eos = { type = "ideal_gas", gamma = 1.4 }""", 10.0e-3, 2.0e-3, 1.0e4, 1.0e-4,
                          "initial_specific_energy = 1600.0")


def dust(tmp, density):
    out = tmp / f"dust_{density}"
    if not run(DUST, out, f'solver.density="{density}"'):
        return
    with h5py.File(last_snapshot(out)) as f:
        x, rho = f["particles/position"][...], f["particles/density"][...]
    inside = x[:, 0] < 0.6 * 20.0e-3  # the kernel complete (R(t) = 20 mm)
    err = float(np.max(np.abs(rho[inside] / 250.0 - 1.0)))
    check(err < 0.05, f"pressureless stretch to 2 R ({density}): rho = rho0/4 within 5% in "
                      f"{inside.sum()} rings ({err:.1e})")
    check(float(x[:, 0].min()) > 0.0, f"pressureless stretch ({density}): no ring at r < 0")


RODS = """
[run]
title = "copper rod into an aluminium rod, rz"
dimension = 2
geometry = "rz"
end_time = 8.0e-6
[[material]]
name = "copper"
density = 8930.0
eos = { type = "mie_gruneisen", c0 = 3940.0, s = 1.49, gamma0 = 2.02 }
strength = { type = "von_mises", shear_modulus = 46.0e9, yield_stress = 0.2e9 }
[[material]]
name = "al"
density = 2700.0
eos = { type = "mie_gruneisen", c0 = 5330.0, s = 1.34, gamma0 = 2.0 }
strength = { type = "von_mises", shear_modulus = 26.0e9, yield_stress = 0.3e9 }
[[body]]
name = "striker"
material = "copper"
shape = { type = "box", min = [0.0, 0.0], max = [2.0e-3, 6.0e-3] }
spacing = 2.0e-4
velocity = [0.0, -600.0]
[[body]]
name = "target"
material = "al"
shape = { type = "box", min = [0.0, -10.2e-3], max = [5.0e-3, -0.2e-3] }
spacing = 2.0e-4
[output]
directory = "unused"
every = 1.0e-6
fields = ["velocity"]
"""


def mpm_stretch(tmp):
    """The uniform radial stretch with MPM (walls at both ends for the periodic boundary)."""
    out = tmp / "elastic_mpm"
    if not run(ELASTIC_WALLS, out, 'solver.method="mpm"'):
        return
    r, inside, exact, _ = stretch_state(out)
    for name, tol in (("density", 1e-4), ("sigma_rr", 1e-2), ("sigma_zz", 1e-2), ("sigma_tt", 1e-2)):
        got, want = exact[name]
        err = float(np.max(np.abs(got[inside] - want))) / abs(want)
        check(err < tol, f"uniform radial stretch (MPM): {name} within {tol:g} of exact in "
                         f"{inside.sum()} interior rings, axis included ({err:.1e})")
    # The points' own (FLIP) velocities: within 3% beyond two cells from the axis (measured 2.0%);
    # within the first cell they oscillate about the exact value by up to half of it (6 mm/s
    # against the rim's 2 m/s): ring masses bias the node velocities near the axis, a known
    # weakness of Cartesian shape functions in axisymmetric MPM (decks/README.md).
    got, want = exact["v_r/r"]
    err = np.abs(got / want - 1.0)
    far = inside & (r > 2 * 0.5e-3)
    check(float(err[far].max()) < 0.03, f"uniform radial stretch (MPM): v_r/r within 3% beyond two "
                                        f"cells from the axis ({float(err[far].max()):.1e})")
    print(f"     MPM: v_r/r of the rings within one cell of the axis off by "
          f"{float(err[inside & (r < 0.5e-3)].max()):.2f}")


def rods(tmp, *sets, energy=1e-4):
    label = " (MPM)" if sets else ""
    out = tmp / f"rods{len(sets)}"
    if not run(RODS, out, *sets, ranks=2):
        return
    h = np.genfromtxt(out / "history.csv", delimiter=",", names=True)
    pz, E = h["momentum_y"], h["total_energy"]
    dp = float(np.max(np.abs(pz - pz[0]))) / abs(pz[0])
    dE = float(np.max(np.abs(E - E[0]))) / E[0]
    check(dp < 1e-12, f"rod impact (rz){label}: momentum along z conserved to round-off ({dp:.1e})")
    check(dE < energy, f"rod impact (rz){label}: total energy within {energy:g} ({dE:.1e})")
    lowest = min(float(h5py.File(f)["particles/position"][:, 0].min())
                 for f in (out / "snapshots").glob("snap_*.h5"))
    check(lowest > 0.0,
          f"rod impact (rz){label}: no ring at r < 0 in any snapshot (lowest r {lowest:.2e} m)")


def taylor(tmp):
    loader = importlib.machinery.SourceFileLoader("taylor", str(SRC / "tools" / "taylor"))
    spec = importlib.util.spec_from_loader("taylor", loader)
    tool = importlib.util.module_from_spec(spec)
    loader.exec_module(tool)
    header = (SRC / "decks" / "taylor_bar_4340_3d.toml").read_text()
    m3 = re.search(r"Measured \(tools/taylor\) at the shipped resolution: ([0-9.]+) mm, ([0-9.]+) mm",
                   header)
    out = tmp / "taylor_4340_rz"
    if not run((SRC / "decks" / "taylor_bar_4340_rz.toml").read_text(), out, ranks=2):
        return
    m = tool.measure(out)
    for name, got, want in (("length", m["length"], float(m3.group(1)) * 1e-3),
                            ("face diameter", m["diameter"], float(m3.group(2)) * 1e-3)):
        err = got / want - 1.0
        check(abs(err) < 0.02, f"4340 Taylor bar: rz {name} {got * 1e3:.2f} mm within 2% of the 3D "
                               f"run's {want * 1e3:.2f} mm ({err * 100:+.2f}%)")
    check(m["lowest"] >= 0.0, "4340 Taylor bar (rz): no particle below the wall")


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    elastic(tmp, "corrected gradient", 1e-4, 'solver.velocity_gradient="corrected"')
    elastic(tmp, "plain gradient", 1e-2)
    elastic(tmp, "ASPH", 1e-2, 'solver.method="asph"')
    dust(tmp, "continuity")
    dust(tmp, "summation")
    rods(tmp)
    mpm_stretch(tmp)
    # MPM conserves momentum to round-off too; its energy to truncation error (measured 1.8e-3,
    # no viscosity at the 600 m/s impact's shocks).
    rods(tmp, 'solver.method="mpm"', energy=1e-2)
    taylor(tmp)
sys.exit(1 if failures else 0)
