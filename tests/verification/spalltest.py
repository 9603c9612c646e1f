"""What the verification scripts share: a check list that reports as it goes, spall runs under
mpirun that record a failed run as a failed check, and snapshot and CSV readers.

A script: `from spalltest import Checks`, `t = Checks()`, `t.check(ok, message)`,
`t.run(deck, out, *sets, ranks=2)`, ..., and `t.finish()` last (exit 1 when a check failed).
"""
import csv
import subprocess
import sys

import h5py
import numpy as np


class Checks:
    def __init__(self, spall=None):
        self.spall = spall or sys.argv[1]
        self.failures = []

    def check(self, ok, message):
        print(("ok   " if ok else "FAIL ") + message)
        if not ok:
            self.failures.append(message)
        return ok

    def run(self, deck, out, *sets, ranks=1, restart=None):
        """spall run DECK --output OUT --set ... on `ranks` ranks; False (and a failed check
        naming the run and its stderr) when it exits non-zero."""
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), self.spall,
               "run", str(deck), "--output", str(out), "--quiet"]
        for s in sets:
            cmd += ["--set", s]
        if restart:
            cmd += ["--restart", restart]
        p = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
        if p.returncode != 0:
            self.check(False, f"{out.name}: exit {p.returncode}\n{p.stderr[-2000:]}")
            return False
        return True

    def finish(self):
        if self.failures:
            print(f"{len(self.failures)} failed")
            sys.exit(1)
        print("all passed")


def snapshot(out, time):
    """The particles of OUT's snapshot at `time` (s), every field, sorted by id; None if none."""
    for f in sorted((out / "snapshots").glob("*.h5")):
        with h5py.File(f) as h:
            if abs(h.attrs["time"] - time) <= 1e-9 * max(time, 1e-12):
                g = h["particles"]
                order = np.argsort(g["id"][:])
                return {k: g[k][:][order] for k in g.keys()}
    return None


def rows(path):
    """A CSV file's rows as dicts of strings."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))
