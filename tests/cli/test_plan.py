#!/usr/bin/python3
"""`spall plan` (issue 66, item 5): a deck's decomposition for virtual ranks, without physics.

1. Its counts are the run's: the ghosts it plans for 1, 2, 3 and 5 ranks equal the ghosts
   history.csv reports at step 0 of real runs (summed over the ranks), on decks that between them
   take every path of the halo: 3D SPH, ASPH's boxes, a periodic 2D box (its own images on one
   rank), rz with graded spacing and time bins, 1D, and the Morton curve. 3 and 5 ranks are
   correctness runs (oversubscribed).
2. Its report is the model it documents (app/Plan.hpp): each rank's step time is recomputed from
   the JSON's counts and costs; the owned particles add up to the deck's; one rank's efficiency is
   1; a step of R ranks on C < R cores is the ranks' summed time over C.
3. Bad input exits 2 with a message and writes nothing: an MPM deck, no or a non-positive rank
   count, a bad --measured directory, more than one process, a deck error at its line.

usage: test_plan.py SPALL SOURCE_DIR
"""
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

SPALL, SRC = str(Path(sys.argv[1]).resolve()), Path(sys.argv[2]).resolve()
ENV = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
           OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
failures = []


def check(ok, message):
    print(("ok   " if ok else "FAIL ") + message, flush=True)
    if not ok:
        failures.append(message)


def plan(deck, ranks, sets, out, *extra):
    cmd = [SPALL, "plan", str(deck), "--ranks", ",".join(map(str, ranks)), "--json", str(out),
           *extra]
    for s in sets:
        cmd += ["--set", s]
    return subprocess.run(cmd, capture_output=True, text=True, env=ENV)


def step0_ghosts(deck, ranks, sets, out):
    cmd = [SPALL, "run", str(deck), "--output", str(out), "--quiet", "--set", "run.max_steps=1"]
    for s in sets:
        cmd += ["--set", s]
    if ranks > 1:
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
    if p.returncode != 0:
        return None, p.stderr[-1500:]
    rows = (out / "history.csv").read_text().splitlines()
    head = rows[0].split(",")
    return int(rows[1].split(",")[head.index("ghosts")]), ""


CASES = [
    ("decks/taylor_bar_3d.toml", ["run.resolution=0.4"], [1, 2, 3]),
    ("decks/taylor_bar_3d.toml", ["run.resolution=0.4", "solver.method=asph"], [2, 5]),
    ("tests/mpi/decks/periodic_shear_2d.toml", [], [1, 2, 3]),
    ("decks/rod_into_steel_semi_infinite_rz.toml", ["run.resolution=0.35"], [2, 3]),
    ("decks/sod_1d.toml", [], [2, 3]),
    ("decks/sedov_3d.toml", ["run.resolution=0.5", 'decomposition.curve="morton"'], [2, 3]),
]

with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    for k, (deck, sets, ranks) in enumerate(CASES):
        label = f"{Path(deck).name} {' '.join(sets)}".strip()
        out = tmp / f"plan{k}.json"
        p = plan(SRC / deck, ranks, sets, out)
        check(p.returncode == 0, f"{label}: spall plan exits 0 ({p.stderr.strip()[-300:]})")
        if p.returncode != 0:
            continue
        report = json.loads(out.read_text())
        planned = {q["ranks"]: q for q in report["plans"]}
        for r in ranks:
            real, err = step0_ghosts(SRC / deck, r, sets, tmp / f"run{k}_{r}")
            check(real == planned[r]["ghosts"],
                  f"{label}: {r} rank(s): planned ghosts {planned[r]['ghosts']}, the run's step 0 "
                  f"{real} {err}")
            check(sum(x["owned"] for x in planned[r]["per_rank"]) == report["particles"],
                  f"{label}: {r} rank(s): owned particles add up to {report['particles']}")

    # ---- the model, recomputed from the report -------------------------------------------
    out = tmp / "model.json"
    p = plan(SRC / "decks/taylor_bar_3d.toml", [1, 4], ["run.resolution=0.5"], out, "--cores", "2",
             "--rate", "2e5", "--ghost-cost", "0.7", "--all-cores-slowdown", "1.3", "--latency",
             "3e-6", "--bandwidth", "1e9")
    check(p.returncode == 0, "the model's plan exits 0")
    if p.returncode == 0:
        rep = json.loads(out.read_text())
        c = rep["costs"]
        check(c["rate"] == 2e5 and c["ghost"] == 0.7 and c["slowdown"] == 1.3 and
              c["latency"] == 3e-6 and c["bandwidth"] == 1e9, "the options' costs are the report's")
        q1, q4 = rep["plans"]
        check(q1["efficiency"] == 1.0 and q1["ghosts"] == 0 and
              abs(q1["step_seconds"] - rep["particles"] / 2e5) < 1e-12 * q1["step_seconds"],
              f"1 rank: efficiency {q1['efficiency']}, no ghosts, N / rate a step (no slowdown)")
        worst, total = 0.0, 0.0
        for m in q4["per_rank"]:
            # Plan.hpp: t_r = s c (N_r + gamma G_r) + k_x m_r lambda + b_r / beta
            #                 + k_c lambda ceil(log2 R)
            t = (c["slowdown"] * (m["owned"] + c["ghost"] * m["ghosts"]) / c["rate"] +
                 rep["exchanges_per_step"] * (m["sends_to"] + m["receives_from"]) * c["latency"] +
                 m["sent"] * rep["halo_bytes"] / c["bandwidth"] +
                 c["collectives_per_step"] * c["latency"] * math.ceil(math.log2(4)))
            # 1e-12 relative: the same sums in another order
            check(abs(t - m["step_seconds"]) <= 1e-12 * t,
                  f"4 ranks: a rank's step {m['step_seconds']:.6g} s is the model's {t:.6g} s")
            check(m["bytes_sent_per_step"] == m["sent"] * rep["halo_bytes"],
                  "bytes sent a step: rows sent x a ghost's bytes")
            worst, total = max(worst, t), total + t
        expect = max(worst, total / 2)  # 4 ranks on 2 cores
        check(abs(q4["step_seconds"] - expect) <= 1e-12 * expect,
              f"4 ranks on 2 cores: step {q4['step_seconds']:.6g} s = max(slowest, sum / 2) "
              f"{expect:.6g} s")
        check(abs(q4["efficiency"] - q1["step_seconds"] / (4 * q4["step_seconds"])) < 1e-12,
              "efficiency = t(1) / (R t(R))")
        check("owned/rank" in p.stdout and "\n4 ranks:\n" in p.stdout,
              "the summary table and the per-rank table are printed")

    # --measured: the rate of a 1-rank run's steady steps (history.csv's second half) and the
    # bytes it accounted beyond its fields.
    run = tmp / "measured"
    subprocess.run([SPALL, "run", str(SRC / "decks/sod_1d.toml"), "--output", str(run), "--quiet",
                    "--set", "run.max_steps=40"], env=ENV, check=True)
    out = tmp / "measured.json"
    p = plan(SRC / "decks/sod_1d.toml", [2], [], out, "--measured", str(run))
    rows = [r.split(",") for r in (run / "history.csv").read_text().splitlines()]
    col = {k: i for i, k in enumerate(rows[0])}
    rows = [[float(x) for x in r] for r in rows[1:]]
    mid, last = rows[len(rows) // 2], rows[-1]
    subs = [r[col["substeps"]] for r in rows[len(rows) // 2 + 1:]]
    rate = (last[col["particles"]] * (last[col["step"]] - mid[col["step"]]) * sum(subs) /
            len(subs) / (last[col["wall_seconds"]] - mid[col["wall_seconds"]]))
    summary = json.loads((run / "summary.json").read_text())
    costs = json.loads(out.read_text())["costs"] if p.returncode == 0 else {}
    # 1e-6: history.csv's wall clock is printed to the millisecond, read back the same way
    check(p.returncode == 0 and abs(costs["rate"] / rate - 1.0) < 1e-6 and
          "second half" in costs["rate_from"],
          f"--measured: rate {costs.get('rate', 0):.6g} = history's steady rate {rate:.6g}")
    parts = summary["memory_parts"]
    check(abs(costs.get("bytes_per_owned_particle", 0) -
              (parts["accounted"] - parts["particle_fields"])) < 1e-9,
          "--measured: the bytes an owned particle holds beyond its fields, as accounted")

    # ---- bad input ---------------------------------------------------------------------------
    def refused(cmd, expect, what, mpi=False):
        if mpi:
            cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2"] + cmd
        p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, cwd=tmp)
        check(p.returncode == 2 and expect in p.stderr,
              f"{what}: exit {p.returncode} (2), says '{expect}'" +
              ("" if expect in p.stderr else f": {p.stderr.strip()[-300:]}"))

    before = set(tmp.iterdir())
    bad = tmp / "bad.json"
    refused([SPALL, "plan", str(SRC / "decks/two_disks_mpm_2d.toml"), "--ranks", "4", "--json",
             str(bad)], "MPM", "an MPM deck")
    refused([SPALL, "plan", str(SRC / "decks/sod_1d.toml"), "--ranks", "0"], "--ranks",
            "rank count 0")
    refused([SPALL, "plan", str(SRC / "decks/sod_1d.toml")], "--ranks", "no rank count")
    refused([SPALL, "plan", str(SRC / "decks/sod_1d.toml"), "--ranks", "2", "--measured",
             str(tmp / "nowhere")], "summary.json", "a missing --measured run")
    two = tmp / "two_ranks"
    two.mkdir()
    (two / "summary.json").write_text(json.dumps({"dimension": 1, "ranks": 2,
                                                  "threads_per_rank": 1}))
    refused([SPALL, "plan", str(SRC / "decks/sod_1d.toml"), "--ranks", "2", "--measured",
             str(two)], "one rank's", "a 2-rank run as --measured")
    refused([SPALL, "plan", str(SRC / "decks/sod_1d.toml"), "--ranks", "2"], "one process",
            "two processes", mpi=True)
    refused([SPALL, "plan", str(SRC / "decks/sedov_3d.toml"), "--ranks", "2", "--set",
             "run.resolution=0.4"], "energy_source", "what a run refuses at its start")
    deck = tmp / "typo.toml"
    deck.write_text((SRC / "decks/sod_1d.toml").read_text().replace("[run]", "[run]\nend_tme = 1",
                                                                    1))
    refused([SPALL, "plan", str(deck), "--ranks", "2"], f"{deck}:", "a deck error at its line")
    check(set(tmp.iterdir()) - before == {deck, two} and not bad.exists(),
          "refused plans write nothing")

print(f"\n{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
