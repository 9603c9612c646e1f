#!/usr/bin/python3
"""The record of a run is faithful (issue 64).

summary.json is valid JSON whatever the title holds (tabs, newlines, quotes, backslashes,
non-ASCII: read back equal by Python's json), carries the git revision and the command line, and
a failed run writes one too (status "failed", the failure's message); OUT/run.log holds the
banner and the closing lines (also with --quiet), and a failure's message.

For every shipped deck, a short run's OUT/deck.toml
- passes `spall check` from another directory (its jets inline, no file paths left relative to
  the old place),
- writes every default the reader applied (a key of each kind spot-checked: solver.cfl,
  solver.kernel, output.grid), the run's --output as output.directory, and floats in their
  shortest round-trip form (no 17-digit tails such as 6.9999999999999994e-05),
- and run again (`spall run OUT/deck.toml`) gives the same particles bit for bit (every field of
  the last snapshot, tools/compare_snapshots at tolerance 0).
Each deck at run.resolution 0.35 (or its own where that is refused) for 2 steps: the record,
not the physics, is under test (a deck with time bins takes up to 32 substeps a step).

usage: test_deck_as_run.py SPALL SOURCE_DIR
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1")
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def spall(*args, cwd=None):
    return subprocess.run([SPALL, *map(str, args)], capture_output=True, text=True, env=ENV,
                          cwd=cwd, stdin=subprocess.DEVNULL)


FLOAT = re.compile(r"(?<![\w.'\"])[-+]?\d+\.\d+(?:e[-+]?\d+)?(?![\w.])")


def digits(token):
    """Significant digits of a float's text."""
    mantissa = token.lstrip("+-").split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa.rstrip("0")) or 1


def longer_than_needed(text):
    # Python's repr is the shortest text that reads back as the same double.
    return [m.group(0) for m in FLOAT.finditer(text)
            if digits(m.group(0)) > digits(repr(float(m.group(0))))]

def summaries(tmp):
    import json
    title = 'Kupfer \u2013 Sto\u00df\t"quoted" \\ back\nslash \u2205'
    out = tmp / "titled"
    deck = SRC / "decks" / "sod_1d.toml"
    toml_title = json.dumps(title)  # a JSON string is a TOML basic string here
    args = ["run", deck, "--output", out, "--quiet", "--set", f"run.title={toml_title}",
            "--set", "run.max_steps=5"]
    p = spall(*args)
    check(p.returncode == 0, f"a run titled {title!r}" + ("" if p.returncode == 0 else p.stderr))
    if p.returncode == 0:
        try:
            s = json.loads((out / "summary.json").read_text(encoding="utf-8"))
            check(s["title"] == title and s["status"] == "finished" and
                  s["command_line"] == [SPALL, *map(str, args)] and s["git_revision"],
                  f"summary.json reads back: title, status, command line, git {s['git_revision']}")
        except (ValueError, KeyError) as e:
            check(False, f"summary.json is valid JSON with the title: {e}")
        log = (out / "run.log").read_text(encoding="utf-8")
        check(log.startswith("spall ") and "particles" in log and f"output in {out}" in log,
              "run.log holds the banner and the closing lines under --quiet")
    # A time-step collapse at step 0 (tests/mpi/test_failures.py): exit 1, and the record says so.
    failed = tmp / "failed"
    p = spall("run", deck, "--output", failed, "--quiet", "--set", "run.end_time=1e12",
              "--set", "output.every=1e6")
    try:
        s = json.loads((failed / "summary.json").read_text())
        check(p.returncode == 1 and s["status"] == "failed" and
              "time step collapsed" in s["failure"] and s["steps"] == 0,
              f"a failed run's summary.json: status {s['status']!r}, failure "
              f"{s['failure'][:60]!r}...")
    except (OSError, ValueError, KeyError) as e:
        check(False, f"a failed run writes summary.json: {e}; exit {p.returncode}")
    log = (failed / "run.log").read_text() if (failed / "run.log").exists() else ""
    check("error: " in log and "time step collapsed" in log.split("error: ")[-1],
          "run.log ends with the failure's message")


with tempfile.TemporaryDirectory() as d:
    tmp = Path(d)
    summaries(tmp)
    elsewhere = tmp / "elsewhere"
    elsewhere.mkdir()
    for deck in sorted((SRC / "decks").glob("*.toml")):
        name = deck.stem
        first, again = tmp / name, tmp / (name + "_again")
        # Some decks need their own resolution (an energy source's radius, MPM walls on planes).
        for resolution in ("0.35", "1.0"):
            p = spall("run", deck, "--output", first, "--quiet", "--overwrite", "--set",
                      f"run.resolution={resolution}", "--set", "run.max_steps=2")
            if p.returncode != 2:
                break
        if p.returncode != 0:
            check(False, f"{name}: the short run: {p.stderr[-800:]}")
            continue
        # Read from another place, as a user copying a run's record would.
        copy = elsewhere / f"{name}.toml"
        shutil.copy(first / "deck.toml", copy)
        text = copy.read_text()
        c = spall("check", copy, cwd=elsewhere)
        check(c.returncode == 0, f"{name}: spall check of its deck.toml passes elsewhere"
              + ("" if c.returncode == 0 else f": {c.stderr[-600:]}"))
        t = tomllib.loads(text)
        solver, output = t.get("solver", {}), t.get("output", {})
        explicit = "cfl" in solver and "kernel" in solver and "grid" in output
        check(explicit and output.get("directory") == str(first) and
              not any("file" in j for j in t.get("jet", [])),
              f"{name}: defaults written (cfl {solver.get('cfl')}, kernel {solver.get('kernel')}, "
              f"grid {output.get('grid')}), output.directory is --output, jets inline")
        long = longer_than_needed(text)
        check(not long, f"{name}: floats in shortest form" + (f" (not: {long[:3]})" if long else ""))
        r = spall("run", copy, "--output", again, "--quiet")
        if r.returncode != 0:
            check(False, f"{name}: spall run of its deck.toml: {r.stderr[-800:]}")
            continue
        cmp = subprocess.run(["/usr/bin/python3", SRC / "tools" / "compare_snapshots", first, again],
                             capture_output=True, text=True)
        check(cmp.returncode == 0, f"{name}: the deck as run repeats the run bit for bit"
              + ("" if cmp.returncode == 0 else f"\n{cmp.stdout[-1500:]}"))
        shutil.rmtree(first)
        shutil.rmtree(again)
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
