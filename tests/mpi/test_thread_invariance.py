#!/usr/bin/python3
"""Whole decks on 1 thread, 3 threads (oversubscribed: correctness only) and 2 ranks x 2 threads
give the same particle state, matched by id, and the same history, bit for bit: every threaded
loop writes a particle's row from that row's inputs only, the neighbor sums in the list's
canonical order, and the reductions (the time step) combine in a fixed order
(core/Threads.hpp). Each case takes the loops a deck's physics adds: the hydro and solid force
loops, ASPH, the corrected kernel, rz, damage, the cap return, P-alpha, MPM's weights, grid
update, G2P and material update.

usage: test_thread_invariance.py SPALL SOURCE_DIR
"""
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verification"))
from spalltest import Checks, concurrently, final_state  # noqa: E402

SPALL, SRC = Path(sys.argv[1]), Path(sys.argv[2])
checks = Checks()
check, failures = checks.check, checks.failures


def run(deck, ranks, threads, out, sets):
    # More threads than cores here: threads that wait sleep instead of spinning at each barrier.
    # SPALL_THREADED_ROWS=1: every loop in threads, however few its rows (these decks are small).
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_WAIT_POLICY="passive",
               SPALL_THREADED_ROWS="1",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    cmd = [str(SPALL), "run", str(deck), "--output", str(out), "--overwrite", "--quiet"]
    if ranks > 1:
        # Unbound: a rank's threads must not all share the one core Open MPI would bind it to.
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-x",
               "OMP_NUM_THREADS", "-x", "OMP_WAIT_POLICY", "-x", "SPALL_THREADED_ROWS",
               "-np", str(ranks)] + cmd
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        failures.append(f"{deck.name} on {ranks} x {threads}: exit {p.returncode}\n{p.stderr[-2000:]}")
        return False
    # Else a build without OpenMP, or a launcher that drops OMP_NUM_THREADS, would pass untested.
    ran = json.loads((out / "summary.json").read_text())["threads_per_rank"]
    check(ran == threads, f"{deck.name}: {ranks} x {threads} ran {ran} thread(s) per rank")
    return ran == threads


# Short runs: every threaded loop runs at every step, so a few hundred steps take them all (the
# rod and the bar still yield within them).
CASES = [("sod_1d.toml", []),
         ("sedov_3d.toml", ["run.resolution=0.5", "run.max_steps=30"]),
         ("noh_2d.toml", ["run.end_time=0.05", "run.resolution=0.5", "solver.method=asph",
                          "solver.artificial_viscosity.balsara=true"]),
         ("elastic_plate_2d.toml", ["run.max_steps=60"]),
         ("taylor_bar_3d.toml", ["run.resolution=0.4", "run.max_steps=40"]),
         ("taylor_bar_rz.toml", ["run.end_time=5e-6"]),
         # the product stress form with strength (copper on PMMA)
         ("rod_impact_pmma_pad_strength.toml", ["run.end_time=2e-6"]),
         # the confining pressure's surface sums and load, damping
         ("sandstone_confinement_rz.toml", ["run.resolution=0.5", "run.max_steps=150"]),
         ("rock_impact_2d.toml", ["run.end_time=3e-6", 'material.basalt.damage.mode="tensor"']),
         ("sandstone_confined_2d.toml", ["run.end_time=6e-6", "run.resolution=0.5"]),
         ("pumice_impact_2d.toml", ["run.end_time=1.0e-6", "run.resolution=0.5"]),
         ("two_disks_mpm_2d.toml", ["run.end_time=1.0"]),
         # MPM's weights, grid update and G2P: cpGIMP with APIC in 3D, CPDI in 2D
         ("taylor_bar_3d.toml", ["run.resolution=0.4", "run.max_steps=30", "solver.method=mpm",
                                 'solver.mpm.transfer="apic"', 'solver.mpm.shape="cpgimp"']),
         ("stretching_bar_mpm_2d.toml", ["run.end_time=0.005"])]

RUNS = ((1, 1), (1, 3), (2, 2))

with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    # Every run ahead of the comparisons: the single-thread ones first, two at a time (one core
    # each), then the others one by one.
    started = time.time()
    jobs = sorted(((i, r, k) for i in range(len(CASES)) for r, k in RUNS),
                  key=lambda j: j[1] * j[2] > 1)
    ok = dict(zip(jobs, concurrently(
        [(r * k, lambda i=i, r=r, k=k: run(SRC / "decks" / CASES[i][0], r, k,
                                           tmp / f"{CASES[i][0]}_{i}_{r}x{k}", CASES[i][1]))
         for i, r, k in jobs])))
    print(f"     ({len(jobs)} runs in {time.time() - started:.1f} s)")
    for i, (deck, sets) in enumerate(CASES):
        label = deck + (f" ({', '.join(sets)})" if sets else "")
        base = None
        for ranks, threads in RUNS:
            out = tmp / f"{deck}_{i}_{ranks}x{threads}"
            if not ok[(i, ranks, threads)]:
                break
            state, t = final_state(out)
            # Every column but the wall clock's.
            history = np.genfromtxt(out / "history.csv", delimiter=",", names=True)
            history = {k: history[k] for k in history.dtype.names if k != "wall_seconds"}
            if base is None:
                base = (state, t, history)
                continue
            same = t == base[1] and set(state) == set(base[0]) and all(
                np.array_equal(state[k], base[0][k]) for k in base[0])
            differ = [k for k in base[0] if k in state and not np.array_equal(state[k], base[0][k])]
            check(same, f"{label}: {ranks} rank(s) x {threads} threads, final state bit for bit as "
                        f"1 x 1" + ("" if same else f" (differ: {', '.join(differ)})"))
            # The history's totals are sums over ranks, added in rank order (one rank's differ in
            # their last bits from two ranks'): compared on one rank only.
            if ranks == 1:
                same = history.keys() == base[2].keys() and all(
                    np.array_equal(history[k], base[2][k]) for k in history)
                check(same, f"{label}: 1 rank x {threads} threads, history.csv identical (but the wall clock)")

checks.finish()
