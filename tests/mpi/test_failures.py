#!/usr/bin/python3
"""Failures that explain themselves (issue 19):

- a deliberately unstable deck (noh_2d at cfl 5) exits 1 with one message (printed once, on 1
  and 3 ranks) naming the particle, its material and body, the bad field and the step; writes the
  particle's history file (steps up to the failure, the last row non-finite or non-positive) and
  a checkpoint of the last good step, which restarts and meets the same failure at the same step;
  the history file is the same on 1 and 3 ranks, number for number (replay is exact);
- a solid's failing particle (pumice_impact_2d at cfl 5) also gets its F-table and state over
  the replayed steps, the same on 1 and 3 ranks and kept through a restart; `spall element
  --state` on them (the command the message prints) gives its stress history to round-off;
- a run whose energy departs from its books by more than output.max_energy_error stops at the
  same step on 1 and 3 ranks, naming the particle that sets the step, and a restart stops again;
- a collapsed time step at the first step (a floor above the stable step) checkpoints the state
  it has and says which particle set the step;
- a batch log (stdout to a file, through mpirun too) gets plain progress lines, no escape codes.

usage: test_failures.py SPALL SOURCE_DIR
"""
import csv
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

SPALL, SRC = Path(sys.argv[1]), Path(sys.argv[2])
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
NOH = SRC / "decks/noh_2d.toml"
UNSTABLE = ["--set", "solver.cfl=5", "--set", "solver.allow_unstable_cfl=true", "--set",
            "run.resolution=0.5"]
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message, flush=True)
    if not cond:
        failures.append(message)


def run(ranks, args, stdout=subprocess.PIPE):
    cmd = [str(SPALL), "run", *args]
    if ranks > 1:
        cmd = ["mpirun", "-np", str(ranks)] + cmd
    return subprocess.run(cmd, stdout=stdout, stderr=subprocess.PIPE, text=True, env=ENV,
                          stdin=subprocess.DEVNULL, timeout=300)


def parse(stderr):
    m = re.search(r"non-finite state at step (\d+) \(t = [^)]*\): ([a-z_, ]+) of particle id (\d+) "
                  r"\(material '(\w+)', body '(\w+)'\)", stderr)
    return m.groups() if m else None


def history(out, step, pid):
    path = out / f"failure_step{step}_particle{pid}.csv"
    if not path.exists():
        return None
    with open(path) as f:
        return list(csv.DictReader(f))


tmp = Path(tempfile.mkdtemp(prefix="spall-failures-"))
try:
    # ---- non-finite state, 1 rank ----
    out1 = tmp / "one"
    r = run(1, [str(NOH), "--output", str(out1), *UNSTABLE])
    check(r.returncode == 1, f"cfl 5 exits 1 (got {r.returncode})")
    got = parse(r.stderr)
    check(got is not None, "the message names step, field, particle, material and body:\n" + r.stderr)
    step, fields, pid, material, body = got
    check(material == "gas" and body == "gas", "material and body by name")
    check(r.stderr.count("error:") == 1, "one error message")
    for words in ("x reference", "x its body's spacing", "neighbors", "last good state",
                  "--restart latest", "hint:"):
        check(words in r.stderr, f"the message says '{words}'")
    rows = history(out1, step, pid)
    check(rows is not None and len(rows) >= 2, "the particle's history file has rows")
    check(int(rows[-1]["step"]) == int(step), "its last row is the failing step")
    last = rows[-1]
    check(not (float(last["density"]) > 0.0 and all(math.isfinite(float(v)) for k, v in last.items()
                                                        if k != "neighbors")),
          "its last row holds the bad value")
    check(all(float(r_["density"]) > 0.0 for r_ in rows[:-1]), "the rows before are good")
    latest = (out1 / "checkpoints/latest").read_text().strip()
    check(latest == f"ckpt_{int(step) - 1:06d}.h5", f"latest checkpoint is the last good step ({latest})")
    first_history = (out1 / f"failure_step{step}_particle{pid}.csv").read_text()

    # ---- the checkpoint restarts, and the same failure comes back ----
    r2 = run(1, [str(NOH), "--output", str(out1), "--restart", "latest", *UNSTABLE])
    check(r2.returncode == 1 and parse(r2.stderr) == got,
          f"the restart fails the same way at the same step: {parse(r2.stderr)}")
    check((out1 / f"failure_step{step}_particle{pid}.csv").read_text() == first_history,
          "the first run's history file is left alone")

    # ---- 3 ranks: one message, the same particle, the same history ----
    out3 = tmp / "three"
    r3 = run(3, [str(NOH), "--output", str(out3), *UNSTABLE])
    check(r3.returncode != 0, "3 ranks fail too")
    check(parse(r3.stderr) == got, f"3 ranks: the same failure ({parse(r3.stderr)})")
    check(r3.stderr.count("error:") == 1, f"3 ranks: printed once:\n{r3.stderr}")
    check((out3 / f"failure_step{step}_particle{pid}.csv").read_text() == first_history,
          "3 ranks: the same history file, number for number")

    # ---- a solid: the failing particle's F-table, replayed by spall element ----
    pumice = SRC / "decks/pumice_impact_2d.toml"
    solid = {}
    for ranks in (1, 3):
        outs = tmp / f"solid{ranks}"
        r = run(ranks, [str(pumice), "--output", str(outs), *UNSTABLE])
        m = re.search(r"its material alone replays them: spall (element .*)", r.stderr)
        check(r.returncode != 0 and m is not None, f"{ranks} rank(s): the message names the "
              f"F-table and the replay command:\n{r.stderr}")
        if m is None:
            continue
        stem = re.search(r"--table (\S+)\.ftable", m.group(1)).group(1)
        solid[ranks] = (m.group(1).split(), Path(stem + ".ftable").read_text(),
                        Path(stem + "_state.csv").read_text(), outs)
    if 1 in solid and 3 in solid:
        check(solid[1][1] == solid[3][1] and solid[1][2] == solid[3][2],
              "1 and 3 ranks: the same F-table and state, number for number")
        command, table, state, outs = solid[1]
        rows = table.count("\n") - 1
        check(rows >= 3, f"the F-table has the replayed steps ({rows} rows)")
        r = subprocess.run([str(SPALL), *command], capture_output=True, text=True, env=ENV)
        replay = Path(command[command.index("--output") + 1])
        check(r.returncode in (0, 1) and replay.exists(), f"spall element replays it: {r.stderr}")
        with open(replay) as f:
            got_rows = list(csv.DictReader(f))
        want_rows = list(csv.DictReader(state.splitlines()))
        keys = ("sxx", "syy", "szz", "sxy", "pressure")
        peak = max(abs(float(w[k])) for w in want_rows for k in keys)
        worst = max(abs(float(g[k]) - float(w[k])) for g, w in zip(got_rows, want_rows)
                    for k in keys)
        # Round-off: the replay repeats the run's update from the recorded state; the F-table
        # (F = I + dt L per step, in doubles) carries L to ~1e-16 of F, and the stress then grows
        # ~1e30-fold over the replayed steps as the particle blows up, so 1e-10 of the history's
        # peak stress (measured 2e-13).
        check(len(got_rows) == len(want_rows) and worst <= 1e-10 * peak,
              f"the replay gives the recorded stress ({len(got_rows)} of {len(want_rows)} rows, "
              f"worst {worst:.3e} Pa of peak {peak:.3e} Pa)")
        r = run(1, [str(pumice), "--output", str(outs), "--restart", "latest", *UNSTABLE])
        check(r.returncode == 1 and Path(str(outs / Path(command[command.index("--table") + 1]).name))
              .read_text() == table, "a restart into the same failure keeps the first F-table")

    # ---- the energy's books: beyond output.max_energy_error the run stops as a failure ----
    # noh_2d keeps its energy to 1.4e-6 of the scale by step 100 (3e-5 at its end): a bound of
    # 1e-9 stops it at step 100, the first step judged, on any rank count, with the particle
    # that sets the time step, a checkpoint of step 99 and the particle's history; a restart
    # from it meets the same stop. (The default bound, 1, stops the fine 2D ASPH al_al cell at
    # 6 km/s of tools/stress at step 999 instead of letting it crawl for hours: decks/README.md.)
    energy = {}
    for ranks in (1, 3):
        oute = tmp / f"energy{ranks}"
        r = run(ranks, [str(NOH), "--output", str(oute), "--set", "run.resolution=0.5", "--set",
                        "output.max_energy_error=1e-9"])
        m = re.search(r"total energy \S+ J at step (\d+) \(t = [^)]*\) is (\S+) times the energy "
                      r"scale .* the run loses energy\. The time step, \S+ s, is set by particle id "
                      r"(\d+) \(material 'gas', body 'gas'\)", r.stderr)
        check(r.returncode == 1 and m is not None and r.stderr.count("error:") == 1,
              f"{ranks} rank(s): the energy's stop names step and particle, once:\n{r.stderr}")
        if m is None:
            continue
        energy[ranks] = (m.group(1), m.group(3))
        check(m.group(1) == "100" and 1e-9 < float(m.group(2)) < 1e-5,
              f"{ranks} rank(s): at step 100, the first judged, {m.group(2)} of the scale")
        check((oute / "checkpoints/latest").read_text().strip() == "ckpt_000099.h5",
              f"{ranks} rank(s): the last good state (step 99) checkpointed")
        check((oute / f"failure_step100_particle{m.group(3)}.csv").exists(),
              f"{ranks} rank(s): the particle's history written")
    check(energy.get(1) is not None and energy.get(1) == energy.get(3),
          f"the same step and particle on 1 and 3 ranks ({energy})")
    r = run(1, [str(NOH), "--output", str(tmp / "energy1"), "--restart", "latest", "--set",
                "run.resolution=0.5", "--set", "output.max_energy_error=1e-9"])
    check(r.returncode == 1 and "at step 100 " in r.stderr,
          f"a restart from the last good state stops at step 100 again:\n{r.stderr}")

    # ---- a collapsed step: the floor is 1e-10 of the end time ----
    outc = tmp / "collapse"
    r = run(1, [str(SRC / "decks/sod_1d.toml"), "--output", str(outc), "--set", "run.end_time=1e12",
                "--set", "output.every=1e6"])
    m = re.search(r"time step collapsed to \S+ s at step 0 .* set by particle id (\d+) "
                  r"\(material '(\w+)', body '(\w+)'\)", r.stderr)
    check(r.returncode == 1 and m is not None, f"a collapsed step names its particle:\n{r.stderr}")
    check((outc / "checkpoints/latest").read_text().strip() == "ckpt_000000.h5",
          "and checkpoints the state it has")
    # MPM's hints are its own: no neighbor count; with frictionless contact, a point flung
    # faster than any impact (here set off at 200 km/s) is contact's debris.
    for speed, hint in ((0.1, "counts as collapsed"), (2e5, 'MPM and a velocity field per body')):
        r = run(1, [str(SRC / "decks/glancing_disks_mpm_2d.toml"), "--output",
                    str(tmp / f"collapse_mpm{speed:g}"), "--set", "run.end_time=1e12", "--set",
                    "output.every=1e6", "--set", f"body.1.velocity=[{speed}, 0.0]"])
        check(r.returncode == 1 and "time step collapsed" in r.stderr and hint in r.stderr and
              "few neighbors" not in r.stderr, f"an MPM collapse at {speed:g} m/s: {hint}\n{r.stderr}")
    # Frictionless MPM warns of bodies under 2 cells across (they can pass through others): the
    # disks (0.4 m) with cells of 0.25 m; none with the deck's cells.
    for cell, warned in ((0.25, True), (0.0, False)):
        r = run(1, [str(SRC / "decks/glancing_disks_mpm_2d.toml"), "--output",
                    str(tmp / f"thin{cell:g}"), "--set", "run.max_steps=1", "--set",
                    f"solver.mpm.cell_size={cell}"])
        said = "can pass through others unstopped ('lower' 0.4 m, 'upper' 0.4 m)" in r.stderr
        check(r.returncode == 0 and said == warned,
              f"cells of {cell:g} m: {'a' if warned else 'no'} thin-body warning\n{r.stderr}")

    # ---- progress in a batch log ----
    for ranks in (1, 2):
        outp = tmp / f"progress{ranks}"
        logfile = tmp / f"progress{ranks}.log"
        with open(logfile, "w") as f:
            r = run(ranks, [str(SRC / "decks/sod_1d.toml"), "--output", str(outp), "--set",
                            "output.progress_percent=25"], stdout=f)
        text = logfile.read_text()
        lines = [l for l in text.splitlines() if l.startswith("step ")]
        check(r.returncode == 0 and "\r" not in text and "\033" not in text,
              f"{ranks} rank(s): no escape codes in a batch log")
        check(4 <= len(lines) <= 6, f"{ranks} rank(s): a line at every 25% ({len(lines)} lines)")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
