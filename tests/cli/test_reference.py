#!/usr/bin/python3
"""docs/reference.md against the binary: every subcommand and every option that `spall --help`
and `spall SUBCOMMAND --help` print is documented on the page, every command the page's synopsis
names exists, and the output files and columns it states are the ones a run writes (history.csv's
header, the snapshot's root attributes and base fields, penetration.csv's columns). A new option,
column or field makes this fail until the page says it.

usage: test_reference.py SPALL_BINARY SOURCE_DIR
"""
import glob
import os
import re
import subprocess
import sys
import tempfile

import h5py

SPALL, SRC = sys.argv[1], sys.argv[2]
PAGE = open(os.path.join(SRC, "docs", "reference.md")).read()
failures = []


def check(name, cond, detail=""):
    print(("ok   " if cond else "FAIL ") + name + (f": {detail}" if detail and not cond else ""))
    if not cond:
        failures.append(name)


def help_text(*args):
    r = subprocess.run([SPALL, *args, "--help"], capture_output=True, text=True, timeout=60)
    check(f"spall {' '.join(args)} --help exits 0", r.returncode == 0, r.stderr)
    return r.stdout


def section(title):
    """The page's section under `## title`, up to the next one."""
    m = re.search(r"^## " + re.escape(title) + r"\n(.*?)(?=^## |\Z)", PAGE, re.S | re.M)
    check(f"the page has a section '{title}'", m is not None)
    return m.group(1) if m else ""


cli = section("Command line")
top = help_text()
subcommands = re.findall(r"^  ([a-z]+) {2,}", top.split("Subcommands:")[1], re.M)
check("spall --help lists subcommands", len(subcommands) >= 5, top)
for sub in subcommands:
    check(f"'{sub}' in the synopsis", re.search(r"^spall " + sub + r"\b", cli, re.M) is not None)
    options = set(re.findall(r"(--[a-z][a-z-]*)", help_text(sub))) - {"--help"}
    for opt in sorted(options):
        check(f"spall {sub} {opt} documented", opt in cli)
for sub in re.findall(r"^spall ([a-z]+)\b", cli, re.M):
    check(f"the synopsis' '{sub}' is a subcommand", sub in subcommands)

codes = section("Exit codes")
for code in ("0", "1", "2"):
    check(f"exit code {code} documented", re.search(r"^\| " + code + r" \|", codes, re.M) is not None)

layout = section("Output layout")
with tempfile.TemporaryDirectory(prefix="spall_reference_") as tmp:
    out = os.path.join(tmp, "run")
    deck = os.path.join(SRC, "decks", "rod_penetration_hydro_rz.toml")
    r = subprocess.run([SPALL, "run", deck, "--output", out, "--quiet", "--set", "run.max_steps=3",
                        "--set", "run.resolution=0.3"], capture_output=True, text=True, timeout=300,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    check("a short rz penetration run finishes", r.returncode == 0, r.stderr)
    if r.returncode == 0:
        for name in ("deck.toml", "history.csv", "summary.json", "penetration.csv",
                     "snapshots/series.xmf", "checkpoints/latest"):
            check(f"{name} written and documented", os.path.exists(os.path.join(out, name)) and
                  ("DIR/" + name) in layout)
        header = open(os.path.join(out, "history.csv")).readline().strip()
        check("history.csv's columns as documented", f"`{header}`" in layout, header)
        header = open(os.path.join(out, "penetration.csv")).readline().strip()
        check("penetration.csv's columns as documented", f"`{header}`" in layout, header)
        snap = sorted(glob.glob(os.path.join(out, "snapshots", "snap_*.h5")))[-1]
        with h5py.File(snap, "r") as f:
            for attr in f.attrs:
                check(f"snapshot attribute {attr} documented", f"`{attr}`" in layout)
            for field in f["particles"]:
                check(f"snapshot field {field} documented", f"`{field}`" in layout)

print(f"{len(failures)} failed" if failures else "all passed")
sys.exit(1 if failures else 0)
