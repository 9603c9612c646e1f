"""What the verification scripts share: a check list that reports as it goes, spall runs under
mpirun that record a failed run as a failed check, and snapshot and CSV readers.

A script: `from spalltest import Checks`, `t = Checks()`, `t.check(ok, message)`,
`t.run(deck, out, *sets, ranks=2)`, ..., and `t.finish()` last (exit 1 when a check failed).
"""
import csv
import os
import subprocess
import sys
import threading

import h5py
import numpy as np


# The cores of the job this thread runs (`concurrently`), where it runs one.
_job = threading.local()


def test_cores():
    """The cores ctest gave the test (SPALL_TEST_CORES, its PROCESSORS), or inside a job of
    `concurrently` the job's."""
    return getattr(_job, "cores", None) or max(1, int(os.environ.get("SPALL_TEST_CORES", "1")))


def mpirun(ranks):
    """The launcher of a run on `ranks` ranks and its environment: each rank runs the test's share
    of its cores (`test_cores`) as threads. A run's particles are the same bit for bit on any
    thread count (tests/mpi/test_thread_invariance.py), so a single-rank run only finishes
    sooner."""
    threads = max(1, test_cores() // ranks)
    return (["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-x", "OMP_NUM_THREADS",
             "-np", str(ranks)], dict(os.environ, OMP_NUM_THREADS=str(threads)))


def concurrently(jobs, cores=None):
    """Runs independent jobs, each (cores it keeps busy, function), side by side on the test's
    cores, and returns their results in order. A job starts when the ones before it have started
    and its cores are free (one that needs more than there are runs alone): single-rank runs go
    two at a time on two cores, where one after another they would leave a core idle."""
    cores = cores or test_cores()
    free, turn, results, raised = [cores], [0], [None] * len(jobs), []
    ready = threading.Condition()

    def work(i, need, job):
        need = min(need, cores)
        with ready:
            ready.wait_for(lambda: turn[0] == i and free[0] >= need)
            free[0] -= need
            turn[0] += 1
            ready.notify_all()
        try:
            _job.cores = need
            results[i] = job()
        except BaseException as e:  # raised again in the caller's thread: a crash fails the test
            raised.append(e)
        finally:
            with ready:
                free[0] += need
                ready.notify_all()

    workers = [threading.Thread(target=work, args=(i, need, job))
               for i, (need, job) in enumerate(jobs)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    if raised:
        raise raised[0]
    return results


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

    def run_all(self, runs):
        """Independent runs, each (deck, out, [sets], {ranks, restart}), side by side on the
        test's cores (`concurrently`): a list of what `run` returns."""
        def job(deck, out, sets=(), options=None):
            options = options or {}
            return (options.get("ranks", 1), lambda: self.run(deck, out, *sets, **options))
        return concurrently([job(*r) for r in runs])

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
