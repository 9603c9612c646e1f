#!/usr/bin/python3
"""Writes the F-tables of the cap single-element suite (tests/verification/test_cap_element.py)
from the parameters of cap.toml. Run from anywhere; the tables land beside this script.

- hydrostatic_crush.ftable: F = lambda I, volume strain ln det F from 0 to -0.12.
- hydrostatic_cycle.ftable (Austin 2013, Fig. 4.12): crush to -0.02, release past the tensile
  vertex (plastic dilation of 0.003), crush again to -0.06.
- dp_vertex.ftable, dp_vertex_nonassoc.ftable (after Brannon & Leelavanichkul's vertex test,
  Austin Sec. 4.1.1.3; legs ours): fixed eigenvectors, deviator along +-diag(2,-1,-1)/sqrt6.
  1 hydrostatic compression to I1 = -60 MPa; 2 loading along the return direction P = C:M, which
  yields halfway and then dwells at the yield point; 3 a deviatoric reversal that yields halfway
  on the other side; 4 a trial stress rate along the yield surface's normal N (not P), which
  slides the stress to the vertex and holds it there.
- uniaxial_strain_cap.ftable: F11 from 1 to 0.96 and back to 0.98 (Fig. 4.10a, b).

usage: make_cap_tables.py
"""
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
K, G, PEAK, FS = 15.7e9, 15.0e9, 20.99e6, 0.435438
P0, P1, P3 = -30.0e6, 5.9e-11, 0.189
UNIT = [2 / math.sqrt(6), -1 / math.sqrt(6), -1 / math.sqrt(6)]


def write(name, header, rows):
    with open(HERE / name, "w") as f:
        for line in header.strip().splitlines():
            f.write(f"# {line}\n")
        f.write("# Columns: t F11 F12 F13 F21 F22 F23 F31 F32 F33 (written by make_cap_tables.py)\n")
        for t, F in rows:
            f.write(f"{t:.6g} {F[0]:.17g} 0 0  0 {F[1]:.17g} 0  0 0 {F[2]:.17g}\n")


def diagonal(ev, e):
    """F = diag(exp(ev/3 + e u)): volume log strain ev, deviatoric log strain e along UNIT."""
    return [math.exp(ev / 3 + e * u) for u in UNIT]


def legs(points, per_leg):
    """Rows through (ev, e) points, per_leg rows a leg, t = 1 per row."""
    rows, t = [(0.0, diagonal(*points[0]))], 0.0
    for (a, b) in zip(points, points[1:]):
        for k in range(1, per_leg + 1):
            s = k / per_leg
            t += 1.0
            rows.append((t, diagonal(a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]))))
    return rows


def crushed(ev):
    """eps_v^p on the hydrostatic crush at total volume strain ev: I1 = 3K (ev - p) = X(p)."""
    lo, hi = -P3 * (1 - 1e-12), 0.0
    for _ in range(200):
        p = 0.5 * (lo + hi)
        X = P0 + math.log1p(p / P3) / P1
        if 3 * K * (ev - p) - X > 0:  # I1 above the cap: less compaction than p
            lo = p
        else:
            hi = p
    return 0.5 * (lo + hi)


write("hydrostatic_crush.ftable", """
Hydrostatic compression, volume log strain 0 to -0.12 (the cap at crush_p0 = -30 MPa is reached
at -6.4e-4; then the crush curve).""", legs([(0.0, 0.0), (-0.12, 0.0)], 60))

p1 = crushed(-0.02)
X1 = P0 + math.log1p(p1 / P3) / P1
ev2 = -0.02 + (PEAK - X1) / (3 * K) + 0.003
write("hydrostatic_cycle.ftable", f"""
Austin (2013), Fig. 4.12: crush to volume log strain -0.02 (X = {X1:.4g} Pa), release past the
tensile vertex by 0.003 of plastic dilation (to {ev2:.6g}), crush again to -0.06.""",
      legs([(0.0, 0.0), (-0.02, 0.0), (ev2, 0.0), (-0.06, 0.0)], 40))

for name, dil in (("dp_vertex.ftable", 1.0), ("dp_vertex_nonassoc.ftable", 0.3)):
    I1a = -60.0e6
    ev1 = I1a / (3 * K)
    # leg 2: (dI1, dq) = s (9 K dil fs, G); the surface q = fs (PEAK - I1) is met at s*.
    s_star = FS * (PEAK - I1a) / (G + 9 * K * dil * FS * FS)
    ev2 = ev1 + 3 * dil * FS * 2 * s_star   # dI1 / 3K
    e2 = math.sqrt(2) * s_star              # |de| = |dS| / 2G = sqrt2 dq / 2G
    I1y, qy = I1a + 9 * K * dil * FS * s_star, G * s_star
    # leg 3: q from +qy to -3qy at constant volume (yield at -qy, halfway)
    e3 = e2 - math.sqrt(2) * 4 * qy / (2 * G)
    # leg 4: dsigma = c N, N = n/sqrt2 + fs I on the negative side: dI1 = 3 c fs, dq = -c/2;
    # c sized to carry I1 twice the distance to the vertex.
    c = 2 * (PEAK - I1y) / (3 * FS)
    ev4 = ev2 + 3 * c * FS / (3 * K)
    e4 = e3 - (c / math.sqrt(2)) / (2 * G)
    write(name, f"""
Drucker-Prager vertex test (after Brannon & Leelavanichkul; Austin 2013, Sec. 4.1.1.3), dilatancy
{dil}: hydrostatic to I1 = -60 MPa; along P (yield halfway at I1 = {I1y:.5g}, q = {qy:.5g}, then a
dwell); deviatoric reversal (yield halfway); along the normal N; hydrostatic extension to the vertex.""",
          legs([(0.0, 0.0), (ev1, 0.0), (ev2, e2), (ev2, e3), (ev4, e4),
                (ev4 + 300.0e6 / (3 * K), e4)], 20))

rows, t = [], 0.0
for k, lam in enumerate([1.0 - 0.04 * j / 40 for j in range(41)] +
                        [0.96 + 0.02 * j / 20 for j in range(1, 21)]):
    rows.append((float(k), [lam, 1.0, 1.0]))
write("uniaxial_strain_cap.ftable", """
Uniaxial strain: F11 from 1 to 0.96, then back to 0.98 (the path meets the Drucker-Prager line,
then the cap; Austin 2013, Fig. 4.10a, b).""", rows)
# The same with a superimposed rotation about z, 0 to 360 degrees (Austin Sec. 4.1.1.1).
with open(HERE / "uniaxial_strain_cap_rotating.ftable", "w") as f:
    f.write("# uniaxial_strain_cap.ftable with a superimposed rotation about z from 0 to 360 degrees\n")
    f.write("# Columns: t F11 .. F33 theta_deg axis_x axis_y axis_z (written by make_cap_tables.py)\n")
    for k, (t, F) in enumerate(rows):
        theta = 360.0 * k / (len(rows) - 1)
        f.write(f"{t:.6g} {F[0]:.17g} 0 0  0 {F[1]:.17g} 0  0 0 {F[2]:.17g}  {theta:.10g} 0 0 1\n")
