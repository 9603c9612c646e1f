#!/usr/bin/python3
"""Decks that cannot crash the code, end to end: `spall check` (parse, validate, make the
particles) on mutated copies of the shipped decks, and on the absurd values a user can type.
Every run must end in exit 0, or exit 2 with `FILE:LINE:COLUMN: error:` (or `--set ...: error:`)
on stderr, within the time limit: never a signal, a hang or exit 1. The mutations are drawn from a
fixed seed (the same set every run); tools/fuzz is the coverage-guided companion over the
reader alone.

usage: test_deck_mutations.py SPALL SOURCE_DIR [COUNT]
"""
import random
import re
import subprocess
import sys
import tempfile
from pathlib import Path

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
COUNT = int(sys.argv[3]) if len(sys.argv) > 3 else 200
# A deck asking for more particles than the machine holds is refused before it is made; one
# that fits is made (check writes nothing), so the limit is generous: the largest shipped deck at
# resolution 2 takes ~5 s here.
TIMEOUT = 60
ABSURD = ["1e300", "-1e300", "1e-300", "0", "-0.0", "-1", "nan", "inf", "-inf", "1e9", "-7",
          "9223372036854775807", "-9223372036854775808", "1e-12", "3.5", '"text"', "true", "[]",
          "[1e300, 1e300, 1e300]", "{}", "[[1.0]]"]
POSITION = re.compile(r"^(\S+:\d+:\d+|--set \S+): error: ", re.M)
failures = []
rng = random.Random(int(__import__("os").environ.get("SPALL_MUTATION_SEED", "19")))


def check(name, text, sets=()):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / (name + ".toml")
        path.write_text(text.replace('directory = "out', f'directory = "{tmp}/out'))
        cmd = [SPALL, "check", str(path)]
        for s in sets:
            cmd += ["--set", s]
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            failures.append(f"{name}: no answer in {TIMEOUT} s\n{text}")
            return
        ok = r.returncode == 0 or (r.returncode == 2 and POSITION.search(r.stderr))
        if not ok:
            failures.append(f"{name}: exit {r.returncode}\n{r.stderr[-800:]}\n--- deck:\n{text}")


def mutate(text):
    lines = text.splitlines()
    for _ in range(rng.randint(1, 3)):
        i = rng.randrange(len(lines))
        line = lines[i]
        kind = rng.random()
        numbers = list(re.finditer(r"(?<![\w.])[-+]?\d[\d_]*\.?\d*(?:[eE][-+]?\d+)?", line))
        if kind < 0.55 and numbers:
            m = rng.choice(numbers)
            line = line[:m.start()] + rng.choice(ABSURD) + line[m.end():]
        elif kind < 0.7 and '"' in line:
            line = re.sub(r'"[^"]*"', rng.choice(['""', '"box"', '"x.y"', '"' + "a" * 300 + '"']), line,
                          count=1)
        elif kind < 0.8:
            line = ""  # a key or table header gone
        elif kind < 0.9:
            lines.insert(i, line)  # a key twice
        else:
            cut = rng.randrange(len(line) + 1)
            line = line[:cut]  # truncated
        lines[i] = line
    return "\n".join(lines) + "\n"


decks = sorted((SRC / "decks").glob("*.toml"))
for k in range(COUNT):
    deck = rng.choice(decks)
    check(f"mutant{k}_{deck.stem}", mutate(deck.read_text()))

# Absurd values a user can type, through --set on a small deck.
sod = (SRC / "decks/sod_1d.toml").read_text()
for s in ["body.left.spacing=1e300", "body.left.spacing=1e-12", "run.resolution=1e9",
          "run.end_time=-1", "run.end_time=nan", "run.max_steps=-5", "solver.nodes_per_h=1e300",
          "body.left.velocity=[1e308]", "output.every=1e-300", "output.every=1e-10", "solver.cfl=5",
          "material.gas.density=nan", "run.dimension=3", "body.left.jitter=0.7"]:
    check("absurd_" + s.split("=")[0], sod, [s])

# Inputs that once hung or crashed (tools/fuzz keeps them too).
for path in sorted((SRC / "tests/fuzz/regressions").glob("*.toml")):
    check("regression_" + path.stem, path.read_text())

print(f"{COUNT} mutants, the absurd values and the regressions: {len(failures)} failure(s)")
for f in failures[:10]:
    print("FAIL", f)
sys.exit(1 if failures else 0)
