#!/usr/bin/python3
"""Shapes and particles from a file, as a user meets them (issue 64, item 6).

- A lattice body's particles, exported with their volumes and read back as shape "particles"
  (CSV and HDF5), run bit for bit as the lattice body: the file path reaches the same particles,
  masses and h, and nothing else in the run depends on how they were made.
- The deck as run of a particles deck names the file absolutely: `spall check` of it passes from
  another directory.
- A rod with a nose (a union in rz) runs into a block with a conical crater (a difference with a
  polygon), the same on 1 and 3 ranks and through a restart; --set reaches the nose by index.
- Bad input: a missing file at the deck's FILE:LINE:COLUMN, a bad row at the particle file's line
  and column, crossing polygon edges, a 'particles' part in a union, a spacing given to a
  particles body: exit 2, nothing written.

usage: test_shapes.py SPALL SOURCE_DIR
"""
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
sys.path.insert(0, str(SRC / "tools" / "python"))
import spall  # noqa: E402

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1")
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def run(*args, cwd=None):
    return subprocess.run([SPALL, *map(str, args)], capture_output=True, text=True, env=ENV,
                          cwd=cwd, stdin=subprocess.DEVNULL)


def mpirun(n, *args):
    return subprocess.run(["mpirun", "--oversubscribe", "-np", str(n), SPALL, *map(str, args)],
                          capture_output=True, text=True, env=ENV, stdin=subprocess.DEVNULL)


def same(a, b):
    cmp = subprocess.run(["/usr/bin/python3", SRC / "tools" / "compare_snapshots", a, b],
                         capture_output=True, text=True)
    return cmp.returncode == 0, cmp.stdout[-1200:]


TAYLOR = SRC / "decks" / "taylor_bar_steel_3d.toml"
# The bar's lattice body, then the same bar as its particles: every other line of the deck kept.
BAR_SHAPE = ('shape = { type = "cylinder", base = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], '
             'radius = 3.2e-3, length = 32.4e-3 }')


def particles_deck(tmp, file):
    text = TAYLOR.read_text()
    assert BAR_SHAPE in text, "taylor_bar_steel_3d.toml's shape line moved"
    lines = []
    for line in text.replace(BAR_SHAPE, f'shape = {{ type = "particles", file = "{file}" }}') \
                    .splitlines():
        if line.startswith("spacing = "):
            continue  # a file's particles take no spacing
        lines.append(line)
    deck = tmp / f"bar_from_{Path(file).suffix[1:]}.toml"
    deck.write_text("\n".join(lines) + "\n")
    return deck


def export(tmp):
    """Runs the lattice bar, writes its t = 0 particles (in id order) as CSV and HDF5."""
    resolution = 0.35
    lattice = tmp / "lattice"
    p = run("run", TAYLOR, "--output", lattice, "--quiet", "--set",
            f"run.resolution={resolution}", "--set", "run.max_steps=20",
            "--set", "output.every_steps=20")
    check(p.returncode == 0, "the lattice bar runs" + ("" if p.returncode == 0 else p.stderr))
    s0 = spall.Run(lattice).snapshot(0)
    order = np.argsort(s0["id"])
    x = s0["position"][order]
    # The lattice's volume per site, as the generator computes it: (spacing / resolution)^3.
    dx = 3.24e-4 / resolution
    V = np.full(len(x), dx ** 3)
    check(np.allclose(s0["mass"][order], 7830.0 * V, rtol=1e-15, atol=0),
          f"the bar's masses are rho dx^3 ({len(x)} particles)")
    with open(tmp / "bar.csv", "w") as f:
        f.write("# the lattice bar's particles at t = 0, by id\nx,y,z,volume\n")
        for (a, b, c), v in zip(x, V):
            f.write(f"{a!r},{b!r},{c!r},{v!r}\n")
    with h5py.File(tmp / "bar.h5", "w") as h:
        h["position"] = x
        h["volume"] = V
    return lattice


def particles_round_trip(tmp):
    lattice = export(tmp)
    for file in ("bar.csv", "bar.h5"):
        deck = particles_deck(tmp, file)
        out = tmp / f"from_{file}"
        p = run("run", deck, "--output", out, "--quiet", "--set", "run.max_steps=20",
                "--set", "output.every_steps=20")
        if p.returncode != 0:
            check(False, f"the bar from {file} runs: {p.stderr[-800:]}")
            continue
        ok, text = same(lattice, out)
        check(ok, f"the bar from {file} runs bit for bit as the lattice bar (20 steps)"
              + ("" if ok else "\n" + text))
        if file.endswith(".csv"):  # every rank reads the file: 3 ranks give the same bits
            three = tmp / "from_csv_3"
            p = mpirun(3, "run", deck, "--output", three, "--quiet", "--set", "run.max_steps=20",
                       "--set", "output.every_steps=20")
            ok, text = same(lattice, three) if p.returncode == 0 else (False, p.stderr[-800:])
            check(ok, "the bar from bar.csv on 3 ranks: the lattice bar's bits"
                  + ("" if ok else "\n" + text))
        # The record names the file absolutely: checked again from elsewhere.
        elsewhere = tmp / "elsewhere"
        elsewhere.mkdir(exist_ok=True)
        copy = elsewhere / f"{deck.stem}_as_run.toml"
        copy.write_text((out / "deck.toml").read_text())
        c = run("check", copy, cwd=elsewhere)
        check(c.returncode == 0 and str(tmp / file) in copy.read_text(),
              f"the deck as run of the bar from {file} names it absolutely and checks elsewhere"
              + ("" if c.returncode == 0 else ": " + c.stderr[-400:]))


NOSED = """[run]
dimension = 2
geometry = "rz"
end_time = 2.0e-6
[[material]]
name = "w"
library = "tungsten_alloy"
[[material]]
name = "steel"
library = "steel_4340"
[[body]]
name = "rod"
material = "w"
shape = { type = "union", shapes = [{ type = "box", min = [0.0, 4.25e-3], max = [2.0e-3, 24.0e-3] },
          { type = "ogive", base = [0.0, 4.25e-3], axis = [0.0, -1.0], radius = 2.0e-3, length = 4.0e-3 }] }
spacing = 5.0e-4
velocity = [0.0, -1500.0]
[[body]]
name = "block"
material = "steel"
shape = { type = "difference", from = { type = "box", min = [0.0, -20.0e-3], max = [15.0e-3, 0.0] }, minus = [
          { type = "polygon", points = [[0.0, -3.0e-3], [3.0e-3, 0.0], [0.0, 0.0]] }] }
spacing = 5.0e-4
[output]
directory = "unused"
[penetration]
penetrator = ["rod"]
target = "block"
surface = [0.0, 0.0]
direction = [0.0, -1.0]
"""


def nosed_rod(tmp):
    deck = tmp / "nosed.toml"
    deck.write_text(NOSED)
    out = tmp / "nosed"
    p = run("run", deck, "--output", out, "--quiet", "--set", "output.every=1.0e-6")
    check(p.returncode == 0, "an ogive-nosed rod (a union) runs into a block"
          + ("" if p.returncode == 0 else ": " + p.stderr[-600:]))
    # On 3 ranks, stopped at 1 us and restarted: the same particles.
    three = tmp / "nosed_3"
    p = mpirun(3, "run", deck, "--output", three, "--quiet", "--set", "run.end_time=1.0e-6",
               "--set", "output.every=1.0e-6")
    r = mpirun(3, "run", deck, "--output", three, "--quiet", "--restart", "latest",
               "--set", "output.every=1.0e-6")
    ok, text = same(out, three) if p.returncode == r.returncode == 0 else (False, p.stderr + r.stderr)
    check(ok, "the nosed rod on 3 ranks through a restart: the 1-rank run's bits"
          + ("" if ok else "\n" + text[-800:]))
    # A blunter nose at --set (2.5 mm, its tip 1.5 mm further from the block): less mass.
    shorter = run("check", deck, "--set", "body.rod.shape.shapes.2.length=2.5e-3")
    base = run("check", deck)
    mass = lambda text: float(text.split("body       rod")[1].split("mass")[1].split()[0])
    ok = shorter.returncode == 0 and base.returncode == 0
    check(ok and mass(shorter.stdout) < mass(base.stdout),
          "--set body.rod.shape.shapes.2.length reaches the nose"
          + (f" ({mass(base.stdout):.4g} -> {mass(shorter.stdout):.4g} kg)" if ok else
             ": " + shorter.stderr))


def refused(tmp, name, deck_text, files, where, what):
    for fname, content in files.items():
        (tmp / fname).write_text(content)
    deck = tmp / f"{name}.toml"
    deck.write_text(deck_text)
    out = tmp / f"out_{name}"
    p = run("run", deck, "--output", out)
    first = p.stderr.strip().splitlines()[0] if p.stderr.strip() else ""
    check(p.returncode == 2 and first.startswith(where) and what in first and not out.exists(),
          f"{name}: exit {p.returncode}, {first!r}")


def bad_input(tmp):
    head = ('[run]\ndimension = 2\ngeometry = "rz"\nend_time = 1.0e-6\n[[material]]\n'
            'name = "w"\nlibrary = "tungsten_alloy"\n[[body]]\nname = "b"\nmaterial = "w"\n')
    tail = '[output]\ndirectory = "unused"\n'
    d = str(tmp)
    refused(tmp, "missing_file", head + 'shape = { type = "particles", file = "none.csv" }\n'
            + tail, {}, f"{d}/missing_file.toml:11:38", "names no file")
    refused(tmp, "bad_row", head + 'shape = { type = "particles", file = "bad.csv" }\n' + tail,
            {"bad.csv": "r,z,volume\n1e-3,0.0,1e-8\n2e-3,oops,1e-8\n"}, f"{d}/bad.csv:3:6",
            "'oops' is not a finite number")
    refused(tmp, "bad_volume", head + 'shape = { type = "particles", file = "bad.csv" }\n' + tail,
            {"bad.csv": "r, z, volume\n1e-3, 0.0, -1e-8\n"}, f"{d}/bad.csv:2:12",
            "volumes must be > 0")
    refused(tmp, "spacing_given", head + 'shape = { type = "particles", file = "good.csv" }\n'
            'spacing = 1.0e-3\n' + tail, {"good.csv": "r,z,volume\n1e-3,0.0,1e-8\n"},
            f"{d}/spacing_given.toml:12:11", "is for lattice shapes")
    refused(tmp, "bow_tie", head + 'shape = { type = "polygon", points = [[0.0, 0.0], [1.0, 1.0], '
            '[1.0, 0.0], [0.0, 1.0]] }\nspacing = 0.1\n' + tail, {},
            f"{d}/bow_tie.toml:11:", "cross")
    refused(tmp, "particles_in_union", head + 'shape = { type = "union", shapes = [{ type = "box", '
            'min = [0.0, 0.0], max = [1.0, 1.0] }, { type = "particles", file = "good.csv" }] }\n'
            'spacing = 0.1\n' + tail, {"good.csv": "r,z,volume\n1e-3,0.0,1e-8\n"},
            f"{d}/particles_in_union.toml:11:", "a file's particles are a body of their own")
    refused(tmp, "cone_off_axis", head + 'shape = { type = "cone", base = [1.0, 0.0], axis = '
            '[0.0, 1.0], radius = 0.5, length = 1.0 }\nspacing = 0.1\n' + tail, {},
            f"{d}/cone_off_axis.toml:11:", "turns about the axis")


with tempfile.TemporaryDirectory() as d:
    tmp = Path(d)
    particles_round_trip(tmp)
    nosed_rod(tmp)
    bad_input(tmp)

print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
