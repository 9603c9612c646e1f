#!/usr/bin/python3
"""tools/jet_layout (a discrete jet's cylinders as they fly when the tip arrives, one rz body)
against closed forms, Austin's published totals and the deck built from it.

- A synthetic three-cylinder jet: the tip's front at the standoff; the second cylinder's front
  V_2 (t_2 - t_1) behind it (a gap); the third would reach into the second (an overlap) and
  starts at its back instead; the summary's gaps, overlaps and the tail's shift are those numbers
  (1e-9 m: the boxes are printed to 8 significant figures of millimetre-scale values).
- Austin's jet (decks/jets/austin_discrete_jet.csv): 154 cylinders, collapsed length 79.5 mm,
  10.10 g at his 19,235 kg/m^3, and at 3266 m/s 33 N s and 54 kJ, as his Sec. 6.4 gives them
  (to the figures he prints).
- decks/discrete_jet_into_sandstone_rz.toml holds the tool's shape for that jet, line for line
  (the deck is generated, not edited); `spall check` weighs its jet body within 1.5% of 10.10 g
  at run.resolution 0.5, 1 and 2 (the lattice's rings stop at the nearest half spacing to each
  cylinder's radius: measured +1.0%, -0.7%, +0.1%), and its rod variant within 1%.
- A file that is not a jet table exits 2 with the file and line.

usage: test_jet_layout.py SPALL SOURCE_DIR
"""
import re
import subprocess
import sys
import tempfile
from pathlib import Path

SPALL, SRC = Path(sys.argv[1]), Path(sys.argv[2])
sys.path.insert(0, str(SRC / "tests" / "verification"))
from spalltest import Checks  # noqa: E402

TOOL = SRC / "tools" / "jet_layout"
T = Checks(str(SPALL))
check = T.check


def layout(path, *args):
    p = subprocess.run([str(TOOL), str(path), *args], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def boxes(text):
    """(r_max, z_min, z_max) of each printed box."""
    pattern = r"min = \[0\.0, ([-0-9.e+]+)\], max = \[([-0-9.e+]+), ([-0-9.e+]+)\]"
    return [(float(r), float(z0), float(z1)) for z0, r, z1 in re.findall(pattern, text)]


def synthetic(tmp):
    jet = tmp / "jet.csv"
    # Fronts behind the tip's (at 0.1 mm), V_k (t_k - t_1): the second 4000 m/s * 2 us = 8 mm (a
    # gap of 7 mm after the 1 mm tip), the third 3000 m/s * 3 us = 9 mm (0.5 mm after the
    # second's back at 8.5 mm), the fourth 2000 m/s * 4.5 us = 9 mm again: inside the third (9 to
    # 9.4 mm), an overlap of 0.4 mm, closed to start at 9.4 mm.
    jet.write_text("# synthetic\nsegment,radius,length,velocity,insert_time\n"
                   "1,1.0e-3,1.0e-3,5000,1.0e-5\n2,1.5e-3,0.5e-3,4000,1.2e-5\n"
                   "3,2.0e-3,0.4e-3,3000,1.3e-5\n4,2.5e-3,0.3e-3,2000,1.45e-5\n")
    rc, out, err = layout(jet, "--standoff", "1e-4", "--speed", "3000", "--density", "1e6")
    check(rc == 0, f"synthetic jet: exit {rc} {err}")
    b = boxes(out)
    want = [(1.0e-3, 1e-4, 1.1e-3), (1.5e-3, 8.1e-3, 8.6e-3), (2.0e-3, 9.1e-3, 9.5e-3),
            (2.5e-3, 9.5e-3, 9.8e-3)]
    check(len(b) == 4 and all(abs(x - y) < 1e-9 for bb, ww in zip(b, want) for x, y in zip(bb, ww)),
          f"synthetic jet: the boxes where they fly, the overlap closed: {b}")
    check("1 overlaps" in out and "up to 0.400 mm" in out and "moves the tail 0.400 mm back" in out,
          "synthetic jet: one overlap of 0.4 mm, the tail moved 0.4 mm")
    check("gaps 0.000 to 7.000 mm" in out, "synthetic jet: gaps 0 (the closed one) to 7 mm")
    # mass: pi (1 + 2.25 * 0.5 + 4 * 0.4 + 6.25 * 0.3) mm^3 * 1e6 kg/m^3 = 17.593 g
    mass = 3.141592653589793 * (1.0 + 1.125 + 1.6 + 1.875) * 1e-9 * 1e6
    check(f"mass {mass * 1e3:.3f} g" in out, f"synthetic jet: mass {mass * 1e3:.3f} g")


def austin(tmp):
    rc, out, err = layout(SRC / "decks/jets/austin_discrete_jet.csv", "--standoff", "1.875e-4",
                          "--speed", "3266")
    check(rc == 0, f"Austin's jet: exit {rc} {err}")
    check(len(boxes(out)) == 154, "Austin's jet: 154 cylinders")
    m = re.search(r"collapsed length ([0-9.]+) mm", out)
    check(m and abs(float(m.group(1)) - 79.5) < 0.05, "collapsed length 79.5 mm (Austin Sec. 6.4)")
    m = re.search(r"mass ([0-9.]+) g", out)
    check(m and abs(float(m.group(1)) - 10.1) < 0.005, "10.1 g at 19,235 kg/m^3 (Austin)")
    m = re.search(r"; ([0-9.]+) N s and ([0-9.]+) kJ at 3266.0 m/s", out)
    check(m and abs(float(m.group(1)) - 33.0) < 0.05 and abs(float(m.group(2)) - 54.0) < 0.5,
          f"33 N s and 54 kJ at 3266 m/s (Austin): {m.groups() if m else out[-300:]}")
    # The deck carries this shape line for line.
    deck = (SRC / "decks/discrete_jet_into_sandstone_rz.toml").read_text()
    shape = out[out.index('type = "union"'):out.index("]\n# ") + 2]
    check(shape in deck, "the deck's jet is the tool's layout of Austin's jet")
    grams = []
    for res in ("0.5", "1.0", "2.0"):
        p = subprocess.run([str(SPALL), "check", str(SRC / "decks/discrete_jet_into_sandstone_rz.toml"),
                            "--set", f"run.resolution={res}"], capture_output=True, text=True)
        m = re.search(r"body +jet +\d+ particles +mass ([0-9.e+-]+) kg", p.stdout)
        grams.append(float(m.group(1)) * 1e3 if m else float("nan"))
    check(all(abs(g / 10.103 - 1.0) < 0.015 for g in grams),
          f"the deck's jet weighs {', '.join(f'{g:.3f}' for g in grams)} g at resolution "
          "0.5, 1, 2 (10.103 g within 1.5%)")
    p = subprocess.run([str(SPALL), "check", str(SRC / "decks/discrete_jet_into_sandstone_rz.toml"),
                        "--set", 'body.jet.shape={type="box", min=[0.0, 1.875e-4], '
                        'max=[1.45e-3, 79.6875e-3]}'], capture_output=True, text=True)
    m = re.search(r"body +jet +\d+ particles +mass ([0-9.e+-]+) kg", p.stdout)
    check(m and abs(float(m.group(1)) / 10.103e-3 - 1.0) < 0.01,
          f"the rod of the deck's header (2.9 x 79.5 mm) weighs the jet's 10.1 g within 1%: "
          f"{m.group(1) if m else p.stderr}")


def bad_input(tmp):
    bad = tmp / "bad.csv"
    bad.write_text("segment,radius,length,velocity,insert_time\n1,1e-3,abc,100,0\n")
    rc, out, err = layout(bad)
    check(rc == 2 and f"{bad}:2:" in err and out == "",
          f"a value that is not a number: exit 2 at the file's line ({rc}: {err.strip()})")
    bad.write_text("segment,radius,length\n1,1e-3,1e-3\n")
    rc, out, err = layout(bad)
    check(rc == 2 and f"{bad}:1:" in err, f"a header that is not a jet's: exit 2 ({err.strip()})")


def main():
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        synthetic(tmp)
        austin(tmp)
        bad_input(tmp)
    T.finish()


main()
