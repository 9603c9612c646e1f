#!/usr/bin/python3
"""One-rank runs started side by side, as a parameter sweep starts them: each must finish and
write every snapshot, and the same deck must give the same bits in each.

Open MPI places each process's MPI-IO scratch files (the shared file pointer's) in a session
directory. Isolated singletons (OMPI_MCA_ess_singleton_isolated=1) all name theirs alike, so in
one shared temporary directory one run's MPI_Finalize deletes another's files and its next
H5Fcreate fails: 2 of 18 such runs failed here, three at a time. spall gives each singleton a
session directory of its own (parallel/Mpi.hpp, MpiSession). Also: no spall-mpi-*
directory is left behind.
Three runs at a time, eight rounds: every run writes a snapshot per step, so each of the other
runs' finishes falls while it is writing.

usage: test_concurrent_runs.py SPALL_BINARY SOURCE_DIR
"""
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
DECK = SRC / "decks" / "spall_plate_1d.toml"
STEPS, AT_ONCE, ROUNDS = 30, 3, 8
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def last_state(out):
    snaps = sorted((out / "snapshots").glob("snap_*.h5"))
    with h5py.File(snaps[-1], "r") as f:
        return len(snaps), {k: f["particles"][k][()] for k in ("id", "position", "velocity")}


with tempfile.TemporaryDirectory() as tmp:
    # The runs' session directories go under TMPDIR: here, so that what is left can be seen.
    scratch = Path(tmp) / "tmpdir"
    scratch.mkdir()
    reference = None
    for round_ in range(ROUNDS):
        outs = [Path(tmp) / f"r{round_}_{k}" for k in range(AT_ONCE)]
        procs = [subprocess.Popen([SPALL, "run", str(DECK), "--output", str(out), "--quiet",
                                   "--set", f"run.max_steps={STEPS}",
                                   "--set", "output.every_steps=1"],
                                  stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True,
                                  env=dict(os.environ, OMP_NUM_THREADS="1",
                                           TMPDIR=str(scratch)))
                 for out in outs]
        for out, p in zip(outs, procs):
            _, err = p.communicate()
            if p.returncode != 0:
                check(False, f"{out.name}: exit {p.returncode}\n{err[-1500:]}")
                continue
            count, state = last_state(out)
            # A snapshot at step 0 and one per step after it.
            check(count == STEPS + 1, f"{out.name}: {count} snapshots ({STEPS + 1} expected)")
            if reference is None:
                reference = state
            same = all(np.array_equal(state[k], reference[k]) for k in state)
            check(same, f"{out.name}: last snapshot bit for bit the same as the first run's")
    left = sorted(p.name for p in scratch.iterdir())
    check(not left, f"no session directory left behind ({', '.join(left) or 'none'})")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
