"""What the verification scripts share: a check list that reports as it goes, spall runs under
mpirun that record a failed run as a failed check, and snapshot and CSV readers.

A script: `from spalltest import Checks`, `t = Checks()`, `t.check(ok, message)`,
`t.run(deck, out, *sets, ranks=2)`, ..., and `t.finish()` last (exit 1 when a check failed).
"""
import csv
import os
import subprocess
import sys

import h5py
import numpy as np


def mpirun(ranks):
    """The launcher of a run on `ranks` ranks and its environment: each rank runs the test's share
    of the cores ctest gave it (SPALL_TEST_CORES, its PROCESSORS) as threads. A run's particles
    are the same bit for bit on any thread count (tests/mpi/test_thread_invariance.py), so a
    single-rank run only finishes sooner."""
    threads = max(1, int(os.environ.get("SPALL_TEST_CORES", "1")) // ranks)
    return (["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-x", "OMP_NUM_THREADS",
             "-np", str(ranks)], dict(os.environ, OMP_NUM_THREADS=str(threads)))


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
        launcher, env = mpirun(ranks)
        cmd = launcher + [self.spall, "run", str(deck), "--output", str(out), "--quiet"]
        for s in sets:
            cmd += ["--set", s]
        if restart:
            cmd += ["--restart", restart]
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, stdin=subprocess.DEVNULL)
        if p.returncode != 0:
            self.check(False, f"{out.name}: exit {p.returncode}\n{p.stderr[-2000:]}")
            return False
        return True

    def same_particles(self, reference, others, what):
        """Checks that each (label, OUT) of `others` ends at the time of the run in `reference`
        with its particles, every field bit for bit."""
        a, ta = final_state(reference)
        for label, other in others:
            b, tb = final_state(other)
            differ = differing(a, b)
            self.check(ta == tb and not differ,
                       f"{what} against {label}: the same particles bit for bit"
                       + (f" (differ: {differ})" if differ else ""))

    def finish(self):
        """Exits 1, listing the failed checks again (a long log buries them), when any failed."""
        if self.failures:
            print(f"\n{len(self.failures)} failed:")
            for f in self.failures:
                print(" -", f)
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


def final_state(out):
    """The particles of OUT's last snapshot, every field, sorted by id; and its time."""
    snap = sorted((out / "snapshots").glob("snap_*.h5"))[-1]
    with h5py.File(snap, "r") as f:
        g = f["particles"]
        order = np.argsort(g["id"][()])
        return {k: g[k][()][order] for k in g}, f.attrs["time"]


def noh_density(out):
    """Noh 2D (decks/noh_2d.toml): OUT's last snapshot's mean density between 0.25 and 0.75 of
    the shock's radius t/3 (the exact value is 16), and its particle count."""
    s, time = final_state(out)
    r = np.hypot(s["position"][:, 0], s["position"][:, 1])
    shock = time / 3.0
    m = (r > 0.25 * shock) & (r < 0.75 * shock)
    return s["density"][m].mean(), len(r)


def differing(a, b):
    """The fields of final_state's particles `a` that `b` lacks or holds other bits of."""
    return [k for k in a if k not in b or not np.array_equal(a[k], b[k])]


def rows(path):
    """A CSV file's rows as dicts of strings."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))
