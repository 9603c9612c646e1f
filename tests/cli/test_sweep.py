#!/usr/bin/python3
"""tools/sweep on a small strengthless rod into copper (rz), two speeds side by side:
- it runs every value, each in its own directory, two at a time, and hands them to
  tools/penetration (a table row per run);
- interrupted (SIGTERM to the sweep while both run on 2 ranks each: the sweep passes SIGUSR1 on,
  which mpirun forwards), each run checkpoints and stops; the sweep run again resumes both from
  their checkpoints, and each run's penetration.csv then equals an
  uninterrupted run's byte for byte (restarts are bit for bit);
- run a third time it runs nothing (both finished);
- another sweep into the same directory is refused (exit 2) and changes nothing;
- a run that fails (an end time past max_steps is not a failure; a negative cfl is a deck error)
  is reported, the sweep exits 1, and the next sweep leaves it alone;
- --dry-run prints one `spall run` per value with the value's --set; keys joined by '&' move
  together (one run per point, not per combination), a point short of a part exits 2;
- `tools/penetration OUT` reads the sweep's runs in its order;
- --from CHECKPOINT: the block alone, checkpointed while the rod waits (insert_time), shot at two
  speeds from that checkpoint; each run's penetration.csv equals its run from t = 0 byte for
  byte, and its history starts after the checkpoint's step.

usage: test_sweep.py SPALL SOURCE_DIR
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
SWEEP = SRC / "tools" / "sweep"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
failures = []

DECK = """# A strengthless tungsten rod into copper, rz, three rings across the rod: tools/sweep's test.
[run]
title = "sweep test"
dimension = 2
geometry = "rz"
end_time = 20.0e-6
[solver]
method = "sph"
[[material]]
name = "w"
density = 17600.0
eos = { type = "mie_gruneisen", c0 = 4029.0, s = 1.237, gamma0 = 1.54 }
[[material]]
name = "cu"
density = 8930.0
eos = { type = "mie_gruneisen", c0 = 3940.0, s = 1.49, gamma0 = 2.0 }
[[body]]
name = "rod"
material = "w"
shape = { type = "box", min = [0.0, 0.0], max = [1.5e-3, 20.0e-3] }
spacing = 5.0e-4
velocity = [0.0, -2000.0]
[[body]]
name = "block"
material = "cu"
shape = { type = "box", min = [0.0, -40.0e-3], max = [12.0e-3, 0.0] }
spacing = 5.0e-4
[output]
directory = "out/sweep_test"
every = 10.0e-6
[penetration]
penetrator = ["rod"]
target = "block"
surface = [0.0, 0.0]
direction = [0.0, -1.0]
"""


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def sweep(deck, out, *extra):
    return [str(SWEEP), str(deck), "--out", str(out), "--spall", SPALL, "--jobs", "2",
            "--vary", "body.rod.velocity", "[0,-1500]", "[0,-2500]", *extra]


def status(run):
    s = run / "summary.json"
    return json.loads(s.read_text())["status"] if s.exists() else None


def main(tmp):
    deck = tmp / "rod.toml"
    deck.write_text(DECK)
    out = tmp / "sweep"
    names = ["velocity_0_-1500", "velocity_0_-2500"]

    p = subprocess.run(sweep(deck, out, "--dry-run"), capture_output=True, text=True, env=ENV)
    lines = p.stdout.strip().splitlines()
    check(p.returncode == 0 and len(lines) == 2 and "body.rod.velocity=[0,-1500]" in lines[0],
          f"--dry-run: one spall run per value ({len(lines)} lines)")
    check(not out.exists(), "--dry-run writes nothing")
    # Keys joined by '&' move together: two points, not four; a value short of a part is refused.
    linked = [str(SWEEP), str(deck), "--out", str(out), "--spall", SPALL, "--dry-run", "--vary",
              "body.rod.velocity&run.end_time", "[0,-1500]&2e-6", "[0,-2500]&3e-6"]
    p = subprocess.run(linked, capture_output=True, text=True, env=ENV)
    lines = p.stdout.strip().splitlines()
    check(p.returncode == 0 and len(lines) == 2 and
          all(f"body.rod.velocity=[0,-{v}]" in line and f"run.end_time={t}" in line
              for line, v, t in zip(lines, (1500, 2500), ("2e-6", "3e-6"))),
          f"--vary 'K1&K2' 'a1&a2' 'b1&b2': the keys move together ({len(lines)} runs)")
    p = subprocess.run(linked[:-1] + ["[0,-2500]"], capture_output=True, text=True, env=ENV)
    check(p.returncode == 2 and "2 keys" in p.stderr and not out.exists(),
          f"a linked value short of a part: exit 2, said ({p.stderr.strip()[:100]})")

    # Interrupted: SIGTERM once both runs (2 ranks each, through mpirun) have written some rows.
    proc = subprocess.Popen(sweep(deck, out, "--np", "2"), stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env=ENV)
    t0 = time.monotonic()
    while time.monotonic() - t0 < 120:
        rows = [len((out / n / "penetration.csv").read_text().splitlines())
                if (out / n / "penetration.csv").exists() else 0 for n in names]
        if min(rows) > 20:
            break
        time.sleep(0.1)
    proc.send_signal(signal.SIGTERM)
    proc.communicate(timeout=300)
    stopped = [status(out / n) for n in names]
    check(stopped == ["stopped", "stopped"],
          f"SIGTERM to the sweep: both runs checkpoint and stop ({stopped}; exit {proc.returncode})")

    p = subprocess.run(sweep(deck, out, "--penetration"), capture_output=True, text=True, env=ENV)
    check(p.returncode == 0 and p.stdout.count("resumed from its checkpoint") == 2,
          f"the sweep again: both resumed from their checkpoints (exit {p.returncode})\n"
          f"{p.stdout[-1500:]}{p.stderr[-1500:]}")
    check(all(status(out / n) == "finished" for n in names), "both finished")
    check(all(n in p.stdout for n in names) and "U/U_B" in p.stdout,
          "--penetration: tools/penetration's table of both runs")

    for n, v in zip(names, ["[0,-1500]", "[0,-2500]"]):
        ref = tmp / f"ref_{n}"
        subprocess.run([SPALL, "run", str(deck), "--output", str(ref), "--quiet", "--set",
                        f"body.rod.velocity={v}"], check=True, env=ENV,
                       stdin=subprocess.DEVNULL)
        same = (ref / "penetration.csv").read_bytes() == (out / n / "penetration.csv").read_bytes()
        check(same, f"{n}: stopped and resumed, penetration.csv equals the uninterrupted run's")

    p = subprocess.run([str(SRC / "tools" / "penetration"), str(out), "--json"],
                       capture_output=True, text=True)
    runs = json.loads(p.stdout)["runs"] if p.returncode == 0 else []
    check([Path(r["run"]).name for r in runs] == names,
          f"tools/penetration OUT: the sweep's runs in order ({[r.get('run') for r in runs]})")

    p = subprocess.run(sweep(deck, out), capture_output=True, text=True, env=ENV)
    check(p.returncode == 0 and "0 to run" in p.stdout,
          f"a third time: nothing to run ({p.stdout.splitlines()[0] if p.stdout else p.stderr})")

    before = (out / "sweep.json").read_text()
    p = subprocess.run([str(SWEEP), str(deck), "--out", str(out), "--spall", SPALL,
                        "--vary", "run.resolution", "0.5"], capture_output=True, text=True,
                       env=ENV)
    check(p.returncode == 2 and "another sweep" in p.stderr and
          (out / "sweep.json").read_text() == before,
          f"another sweep into the same directory: exit {p.returncode}, refused, unchanged "
          f"({p.stderr.strip()})")

    # --from: the rod listed after the block and joining at 2 us; the block alone to step 20.
    waiting = DECK.replace('velocity = [0.0, -2000.0]\n', 'velocity = [0.0, -2000.0]\n'
                           'insert_time = 2.0e-6\n')
    rod = waiting[waiting.index("[[body]]\nname = \"rod\""):waiting.index("[[body]]\nname = \"block\"")]
    waiting = waiting.replace(rod, "").replace("[output]", rod + "[output]")
    deck2 = tmp / "rod_waits.toml"
    deck2.write_text(waiting)
    settled = tmp / "settled"
    subprocess.run([SPALL, "run", str(deck2), "--output", str(settled), "--quiet", "--set",
                    "run.max_steps=20"], check=True, env=ENV, stdin=subprocess.DEVNULL)
    ckpt = settled / "checkpoints" / (settled / "checkpoints" / "latest").read_text().strip()
    shots = tmp / "shots"
    p = subprocess.run(sweep(deck2, shots, "--from", str(ckpt), "--set", "run.end_time=8e-6"),
                       capture_output=True, text=True, env=ENV)
    check(p.returncode == 0 and p.stdout.count(f"started from {ckpt}") == 2,
          f"--from: both runs started from the checkpoint (exit {p.returncode})\n"
          f"{p.stdout[-800:]}{p.stderr[-800:]}")
    for n, v in zip(names, ["[0,-1500]", "[0,-2500]"]):
        ref = tmp / f"fresh_{n}"
        subprocess.run([SPALL, "run", str(deck2), "--output", str(ref), "--quiet", "--set",
                        f"body.rod.velocity={v}", "--set", "run.end_time=8e-6"], check=True,
                       env=ENV, stdin=subprocess.DEVNULL)
        shot = shots / n
        first = (shot / "history.csv").read_text().splitlines()[1].split(",")[0] \
            if (shot / "history.csv").exists() else "none"
        same = (shot / "penetration.csv").exists() and \
            (ref / "penetration.csv").read_bytes() == (shot / "penetration.csv").read_bytes()
        check(same and first.isdigit() and int(first) > 20,
              f"--from, {n}: penetration.csv equals the run from t = 0; history from step {first}")

    bad = tmp / "bad"
    args = [str(SWEEP), str(deck), "--out", str(bad), "--spall", SPALL,
            "--vary", "solver.cfl", "-1", "0.3", "--set", "run.end_time=2e-6"]
    p = subprocess.run(args, capture_output=True, text=True, env=ENV)
    check(p.returncode == 1 and "cfl_-1" in p.stderr and (bad / "logs" / "cfl_-1.failed").exists() and status(bad / "cfl_0.3") == "finished",
          f"a run with a deck error: the sweep exits 1 and names it; the other finishes "
          f"(exit {p.returncode}: {p.stderr.strip()[-300:]})")
    p = subprocess.run(args, capture_output=True, text=True, env=ENV)
    check("0 to run" in p.stdout,
          f"the sweep again: the failed run left alone ({p.stdout.splitlines()[0]})")


with tempfile.TemporaryDirectory() as d:
    main(Path(d))
print(f"\n{len(failures)} failure(s)" if failures else "\nall passed")
sys.exit(1 if failures else 0)
