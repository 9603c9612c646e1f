#!/usr/bin/python3
"""P-alpha through the single-element driver (`spall element`; issue 16), the same material code
as `spall run` (tests/verification/element/porous.toml).

Uniaxial strain F = diag(lambda, 1, 1): compressed from 1 to 0.8, released to 0.86, compressed
again to 0.66 (full compaction: P > solid_pressure), 200 substeps a row. At every row:
- the density follows F: rho = rho00 / lambda (rho00 = density / alpha0), exactly to round-off;
- the pressure is the porous EOS at the row's state: P = P_eos(alpha rho, e) / alpha (spall's
  Mie-Gruneisen re-implemented), to 1e-12 relative (round-off);
- while compacting (alpha fell in the row), alpha is on the crush curve, |alpha - alpha_c(P)|
  <= 1e-8 (the solve stops at 1e-12 in alpha; alpha_c moves by |alpha_c'| dP/dalpha ~ 1e3 times
  that; measured 1.7e-14: the last Newton step lands far closer);
- while unloading and reloading below the old maximum, alpha stays exactly where it was
  (irreversibility: no pore reopens), and it never grows;
- the solve's cost: EOS evaluations per update (median and worst) printed.
The two-stage material with strength as well (the curve's joint at transition_pressure passed).
Measured: 4 EOS evaluations per compacting update (median and worst), 1 while unloading.
With elastic distension (elastic_sound_speed): the plastic part on the curve and held, alpha =
alpha_p + a(alpha_p) P at every row. Plot: porous_element_plots/alpha_pressure.png (in the
working directory).

usage: test_porous_element.py SPALL SOURCE_DIR
"""
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
DECK = SRC / "tests" / "verification" / "element" / "porous.toml"
from porous_aluminium import ALPHA0, C0, PE, PS, RHO_S, p_eos  # noqa: E402
from porous_aluminium import curve as one_stage  # noqa: E402
from plots import save_plot  # noqa: E402

failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def two_stage(P, Pt=2.0e8, at=1.15, nt=1.5):
    if P <= PE:
        return ALPHA0
    if P >= PS:
        return 1.0
    if P <= Pt:
        return at + (ALPHA0 - at) * ((Pt - P) / (Pt - PE)) ** nt
    return 1 + (at - 1) * ((PS - P) / (PS - Pt)) ** 2


def table(path, lambdas):
    with open(path, "w") as f:
        f.write("# uniaxial strain, F = diag(lambda, 1, 1)\n")
        for t, lam in enumerate(lambdas):
            f.write(f"{t} {lam!r} 0 0  0 1 0  0 0 1\n")


def plot_alpha(plain, elastic):
    """porous_element_plots/alpha_pressure.png: alpha against P along the path, with the curve."""
    def draw(ax):
        Pc = np.linspace(-0.05 * PS, PS, 400)
        ax.plot(Pc / 1e6, [one_stage(x) for x in Pc], "k-", lw=0.8, label="crush curve alpha_c(P)")
        ax.plot(plain["pressure"] / 1e6, plain["porosity_alpha"], "o-", ms=3, label="alpha")
        ax.plot(elastic["pressure"] / 1e6, elastic["porosity_alpha"], "s-", ms=3,
                label="alpha, elastic distension (c_e 2000 m/s)")
        ax.plot(elastic["pressure"] / 1e6, elastic["plastic_distension"], "^", ms=3,
                label="its plastic part alpha_p")
        ax.set_xlabel("pressure (MPa)")
        ax.set_ylabel("distension alpha")
        ax.set_title("P-alpha, uniaxial strain: load, release, reload (porous aluminium)")
    save_plot(PLOTS, "alpha_pressure", draw)


PLOTS = Path.cwd() / "porous_element_plots"
col_plain = None
path = np.concatenate([np.linspace(1.0, 0.8, 41), np.linspace(0.8, 0.86, 13)[1:],
                       np.linspace(0.86, 0.66, 41)[1:]])
with tempfile.TemporaryDirectory() as tmp:
    tab = Path(tmp) / "uniaxial.ftable"
    table(tab, path)
    for name, curve in (("porous_aluminium", one_stage), ("two_stage", two_stage)):
        out = Path(tmp) / f"{name}.csv"
        p = subprocess.run([SPALL, "element", str(DECK), "--material", name, "--table", str(tab),
                            "--output", str(out), "--substeps", "200"],
                           capture_output=True, text=True, stdin=subprocess.DEVNULL)
        check(p.returncode == 0, f"{name}: spall element succeeds ({p.stderr.strip()[-300:]})")
        if p.returncode:
            continue
        rows = list(csv.DictReader(open(out)))
        col = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
        lam, rho, e, P = col["F11"], col["density"], col["specific_internal_energy"], col["pressure"]
        alpha, its = col["porosity_alpha"], col["return_iterations"]
        rho_err = np.max(np.abs(rho * lam / (RHO_S / ALPHA0) - 1))
        check(rho_err < 1e-14, f"{name}: rho = rho00 / lambda ({rho_err:.1e})")
        peos = np.array([p_eos(a * r, en) / a for a, r, en in zip(alpha, rho, e)])
        p_err = np.max(np.abs(peos - P)) / np.max(np.abs(P))
        check(p_err < 1e-12, f"{name}: P = P_eos(alpha rho, e)/alpha ({p_err:.1e} of max P)")
        fell = np.diff(alpha) < 0
        on = np.array([abs(a - curve(pp)) for a, pp in zip(alpha[1:], P[1:])])[fell]
        check(fell.sum() > 40 and np.max(on) < 1e-8,
              f"{name}: compacting rows ({fell.sum()}) on the crush curve ({np.max(on):.1e})")
        unload = slice(41, 53)  # the release, and the reload below the old maximum density
        held = np.all(alpha[41:53] == alpha[40])
        check(held, f"{name}: alpha held at {alpha[40]:.6f} through the release "
                    f"(range {alpha[unload].min():.9f}..{alpha[unload].max():.9f})")
        check(np.all(np.diff(alpha) <= 0), f"{name}: alpha never grows")
        check(alpha[-1] == 1.0,
              f"{name}: compacted to alpha {alpha[-1]:.6f} at lambda = 0.66 (P {P[-1]:.3g} Pa)")
        print(f"     {name}: EOS evaluations a row's last update: median {np.median(its):.0f}, "
              f"worst {its.max():.0f}")
        if name == "porous_aluminium":
            col_plain = col

    # Elastic distension (elastic_sound_speed c_e = 2000 m/s; materials/Porosity.hpp, Eq. 2):
    # the same path. The plastic distension alpha_p takes alpha's place above (on the curve
    # while compacting, held through the release, never growing); alpha = alpha_p + a(alpha_p) P
    # at every row to round-off, a = alpha_p^2/K_s (1 - 1/h^2), h = 1 + (alpha_p - 1)(c_e/c_s0 -
    # 1)/(alpha0 - 1); so the release gives back the elastic part (alpha grows, reversibly).
    CE = 2000.0
    out = Path(tmp) / "elastic.csv"
    p = subprocess.run([SPALL, "element", str(DECK), "--material", "porous_aluminium", "--table",
                        str(tab), "--output", str(out), "--substeps", "200", "--set",
                        f"material.porous_aluminium.porosity.elastic_sound_speed={CE}"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL)
    check(p.returncode == 0, f"elastic: spall element succeeds ({p.stderr.strip()[-300:]})")
    if p.returncode == 0:
        rows = list(csv.DictReader(open(out)))
        el = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
        aP, alpha_el, P_el = el["plastic_distension"], el["porosity_alpha"], el["pressure"]
        h = 1 + (np.minimum(aP, ALPHA0) - 1) * (CE / C0 - 1) / (ALPHA0 - 1)
        a = aP**2 / (RHO_S * C0**2) * (1 - 1 / h**2)
        split = np.max(np.abs(alpha_el - np.maximum(1.0, aP + a * P_el)))
        check(split < 1e-12, f"elastic: alpha = alpha_p + a(alpha_p) P at every row ({split:.1e})")
        peos = np.array([p_eos(x * r, en) / x for x, r, en in
                         zip(alpha_el, el["density"], el["specific_internal_energy"])])
        p_err = np.max(np.abs(peos - P_el)) / np.max(np.abs(P_el))
        check(p_err < 1e-12, f"elastic: P = P_eos(alpha rho, e)/alpha ({p_err:.1e} of max P)")
        fell = np.diff(aP) < 0
        on = np.array([abs(x - one_stage(pp)) for x, pp in zip(aP[1:], P_el[1:])])[fell]
        check(fell.sum() > 40 and np.max(on) < 1e-8,
              f"elastic: compacting rows ({fell.sum()}) with alpha_p on the crush curve "
              f"({np.max(on):.1e})")
        check(np.all(aP[41:53] == aP[40]) and np.all(np.diff(aP) <= 0),
              "elastic: alpha_p held through the release, and never grows")
        check(alpha_el[52] > alpha_el[40] and aP[-1] == 1.0 and alpha_el[-1] == 1.0,
              f"elastic: the release opens the pores elastically ({alpha_el[40]:.6f} -> "
              f"{alpha_el[52]:.6f}); fully compacted at the end")
        plot_alpha(col_plain, el)

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
