#!/usr/bin/python3
"""Checkpoint/restart chains end to end (issue 4's tests):

- exactness: a run to 2T equals a run to T restarted to 2T, bit for bit (particle state, history
  and probe rows), on 1 and on 2 ranks; T is an output time, so both runs take the same steps;
- N to M: a 2-rank checkpoint restarted on 1 and on 3 ranks ends within 1e-12 relative of the
  uninterrupted run (the canonical neighbor order makes it bit for bit; the bound is the issue's);
- crash: SIGKILL mid-run, and SIGKILL inside a checkpoint write (rank 0 dies halfway through the
  data, via the SPALL_TEST_KILL_IN_CHECKPOINT hook), then `--restart latest`: same final state,
  history rows without gaps or duplicates;
- signal: SIGUSR1 (2 ranks, through mpirun) and SIGTERM (1 rank) checkpoint at the next step
  boundary and exit 0 with the resume command; the resumed run ends as the uninterrupted one;
- bad checkpoints (truncated, a flipped data byte, not HDF5, another format version, another
  deck, nothing to restart from) exit 2 on 2 ranks within a timeout (no hang), name the file,
  and write nothing; `--restart latest` with a corrupt newest file falls back and says so;
- a body that has not joined yet (insert_time) may change on restart: another rod into the
  checkpointed block equals that rod's run from t = 0 bit for bit; what the checkpoint holds
  (the block, its material, a rod due before the checkpoint, ids that would move) is refused.

With `long` as the third argument, also the ASPH stretching rod with tensor damage restarted
mid-failure (12 s of 2 cores; in the fast suite its parts are each restarted elsewhere: ASPH in
3D, tensor damage and fragments in the basalt, the damage's failed pairs in the spall plate).

usage: test_restart.py SPALL SOURCE_DIR [long]
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

SPALL, SRC = Path(sys.argv[1]), Path(sys.argv[2])
LONG = len(sys.argv) > 3 and sys.argv[3] == "long"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
SHEAR = SRC / "tests/mpi/decks/periodic_shear_2d.toml"
ROD = SRC / "decks/rod_impact_copper.toml"
# s; a run here takes ~1 s, so hitting this means a hang (sanitizer builds: raise it)
TIMEOUT = float(os.environ.get("SPALL_TEST_TIMEOUT", "120"))
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message, flush=True)
    if not cond:
        failures.append(message)


def command(deck, ranks, out, sets=(), restart=None):
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), str(SPALL), "run",
           str(deck), "--output", str(out), "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    if restart:
        cmd += ["--restart", str(restart)]
    return cmd


def run(deck, ranks, out, sets=(), restart=None, env=ENV, expect=0):
    try:
        p = subprocess.run(command(deck, ranks, out, sets, restart), capture_output=True, text=True,
                           env=env, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        check(False, f"{deck.name} on {ranks} ranks ({out.name}) hung")
        return None
    if expect is not None and p.returncode != expect:
        check(False, f"{deck.name} on {ranks} ranks ({out.name}): exit {p.returncode}, expected "
                     f"{expect}\n{p.stderr[-3000:]}")
    return p


def final_state(out):
    snap = sorted((out / "snapshots").glob("snap_*.h5"))[-1]
    with h5py.File(snap, "r") as f:
        g = f["particles"]
        order = np.argsort(g["id"][()])
        return {k: g[k][()][order] for k in g}, float(f.attrs["time"]), snap.name


def max_relative(a, b):
    worst = 0.0
    for k in a:
        x, y = a[k].astype(float), b[k].astype(float)
        scale = max(np.max(np.abs(x)), 1e-300)
        worst = max(worst, float(np.max(np.abs(x - y))) / scale if x.size else 0.0)
    return worst


def same_state(ref, out, label, tolerance=0.0, same_index=True):
    a, ta, na = final_state(ref)
    b, tb, nb = final_state(out)
    check(set(a) == set(b) and ta == tb and (na == nb or not same_index),
          f"{label}: final snapshot {nb} at t = {tb} (reference {na} at {ta})")
    if set(a) != set(b) or a["id"].shape != b["id"].shape or not np.array_equal(a["id"], b["id"]):
        check(False, f"{label}: particle sets differ")
        return
    if tolerance == 0.0:
        differ = [k for k in a if not np.array_equal(a[k], b[k])]
        check(not differ, f"{label}: final state bit for bit identical" +
              (f" (differs in {differ})" if differ else ""))
    else:
        d = max_relative(a, b)
        check(d <= tolerance, f"{label}: final state within {tolerance:g} relative (max {d:.2e})")


def stopped_and_restarted(deck, ranks, outs, sets, stop_steps, label):
    """Runs `sets` through, and again stopped after `stop_steps` steps and restarted from its last
    checkpoint; the two final states must agree bit for bit. (The first leg's stop wrote a
    snapshot of its own, so the final snapshots' indices differ.)"""
    full, half = outs / "full", outs / "half"
    run(deck, ranks, full, sets)
    run(deck, ranks, half, [*sets, f"run.max_steps={stop_steps}"])
    run(deck, ranks, half, sets, restart="latest")
    same_state(full, half, label, same_index=False)


def history(out):
    rows = (out / "history.csv").read_text().splitlines()
    header = rows[0].split(",")
    # wall_seconds differs between runs, by nature; so do the ghost and migration counts: a
    # resumed run searches its neighbors at once, the uninterrupted one when its kept lists are
    # used up (solver.neighbor_skin), and ghosts are made and particles change ranks at searches;
    # and the imbalance, a diagnostic of the partition (decomposition.cost = "timed" cuts by
    # measured times). The physics columns must not (sums that ignore the particles' order).
    skip = {header.index(c) for c in ("wall_seconds", "ghosts", "migrated", "imbalance")
            if c in header}
    return [",".join(c for i, c in enumerate(r.split(",")) if i not in skip) for r in rows[1:]]


def same_logs(ref, out, label, exact=True):
    h_ref, h = history(ref), history(out)
    steps = [int(r.split(",")[0]) for r in h]
    check(steps == sorted(set(steps)) and steps == [int(r.split(",")[0]) for r in h_ref],
          f"{label}: history.csv steps 0..{steps[-1]} once each, as in the uninterrupted run")
    if exact:
        check(h == h_ref, f"{label}: history.csv rows identical to the uninterrupted run")
        if (ref / "probes.csv").exists():
            check((ref / "probes.csv").read_text() == (out / "probes.csv").read_text(),
                  f"{label}: probes.csv identical to the uninterrupted run")


def kill_all(proc):
    """SIGKILL to mpirun and every rank at once, as a node failure would. (Open MPI puts the ranks
    in their own process groups, so killing mpirun's group would leave them running.)"""
    pids, frontier = [proc.pid], [proc.pid]
    while frontier:
        out = subprocess.run(["ps", "-o", "pid=", "--ppid", ",".join(map(str, frontier))],
                             capture_output=True, text=True).stdout.split()
        frontier = [int(p) for p in out]
        pids += frontier
    for pid in reversed(pids):
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    proc.wait()


def latest(out):
    p = out / "checkpoints" / "latest"
    return p.read_text().strip() if p.exists() else None


def wait_for_checkpoint(out, min_step, proc):
    """Polls until `latest` names a checkpoint at min_step or later (or the run ends)."""
    deadline = time.time() + TIMEOUT
    while time.time() < deadline and proc.poll() is None:
        name = latest(out)
        if name and int(name[5:-3]) >= min_step:
            return True
        time.sleep(0.005)
    return False


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)

    # ---- exactness, same rank count --------------------------------------------------------
    for ranks in (1, 2):
        full, half = tmp / f"full{ranks}", tmp / f"half{ranks}"
        run(SHEAR, ranks, full, ["run.end_time=0.1"])
        run(SHEAR, ranks, half, ["run.end_time=0.05"])
        check(latest(half) is not None, f"{ranks} rank(s): the run to T ends with a checkpoint")
        run(SHEAR, ranks, half, ["run.end_time=0.1"], restart="latest")
        same_state(full, half, f"shear, {ranks} rank(s), T + restart to 2T vs 2T")
        same_logs(full, half, f"shear, {ranks} rank(s)")
        series = (half / "snapshots" / "series.xmf").read_text()
        check(all(f"snap_00000{k}.h5:/particles/position" in series for k in range(3)) and
              series.count("<Time ") == len(list((half / "snapshots").glob("snap_*.h5"))),
              f"{ranks} rank(s): series.xmf holds snapshots 0-2 after the restart, each once")
        # Restarting a run that already reached its end does nothing, and says so by exit 0.
        before = (half / "history.csv").read_text()
        run(SHEAR, ranks, half, ["run.end_time=0.1"], restart="latest")
        check((half / "history.csv").read_text() == before,
              f"{ranks} rank(s): restarting a finished run adds no rows")

    # Probes and history of a 1D deck with walls and material probes, on 2 ranks.
    rod_full, rod_half = tmp / "rod_full", tmp / "rod_half"
    run(ROD, 2, rod_full, ["run.end_time=6e-6"])
    run(ROD, 2, rod_half, ["run.end_time=3e-6"])
    run(ROD, 2, rod_half, ["run.end_time=6e-6"], restart="latest")
    same_state(rod_full, rod_half, "rod impact, 2 ranks, T + restart")
    same_logs(rod_full, rod_half, "rod impact, 2 ranks")

    # Strength: S, plastic strain and the last velocity gradient are checkpointed too (200 m/s:
    # the material has yielded at the checkpoint).
    rod = SRC / "decks/rod_impact_copper_strength.toml"
    full, half = tmp / "rods_full", tmp / "rods_half"
    run(rod, 1, full, ["run.end_time=6e-6", "body.striker.velocity=[200.0]"])
    run(rod, 1, half, ["run.end_time=3e-6", "body.striker.velocity=[200.0]"])
    run(rod, 1, half, ["run.end_time=6e-6", "body.striker.velocity=[200.0]"], restart="latest")
    same_state(full, half, "rod impact with strength, T + restart")

    # Axisymmetric, mid-mushroom: ring masses and the hoop stress S_tt (in S) are checkpointed.
    stopped_and_restarted(SRC / "decks/taylor_bar_rz.toml", 2, tmp / "rz", ["run.end_time=1e-5"],
                          400, "Taylor bar (rz), 2 ranks, restart mid-flow")
    # ... with Zerilli-Armstrong: the temperature its yield stress reads is checkpointed
    stopped_and_restarted(SRC / "decks/taylor_bar_za_rz.toml", 3, tmp / "za_rz",
                          ["run.end_time=1e-5"], 400, "Taylor bar (rz, Zerilli-Armstrong), 3 ranks, restart mid-flow")

    # Damage: a restart mid-failure (the spall plane opens from 1.75 us): damage, the intact
    # stress and the flaw state are checkpointed, the flaws themselves redrawn from (seed, id).
    spall = SRC / "decks/spall_plate_1d.toml"
    full, half = tmp / "spall_full", tmp / "spall_half"
    run(spall, 2, full, ["run.end_time=2.2e-6"])
    run(spall, 2, half, ["run.end_time=1.8e-6"])
    run(spall, 2, half, ["run.end_time=2.2e-6"], restart="latest")
    same_state(full, half, "spall plate (damage), 2 ranks, restart mid-failure")

    # Tensor damage and fragments in 2D: the damage and strain tensors are checkpointed; the
    # `fragment` field of the snapshots after the restart is found again, identically.
    rock = SRC / "decks/rock_impact_2d.toml"
    tensor = 'material.basalt.damage.mode="tensor"'
    full, half = tmp / "rock_full", tmp / "rock_half"
    run(rock, 2, full, ["run.end_time=4e-6", tensor])
    run(rock, 2, half, ["run.end_time=2e-6", tensor])
    run(rock, 2, half, ["run.end_time=4e-6", tensor], restart="latest")
    same_state(full, half, "rock impact (tensor damage, fragments), 2 ranks, restart")

    # ASPH with tensor damage, restarted while the rod is being cut (step 4300, t = 37.9 us: 2.8%
    # failed at 38 us). Stopped by step count: an end time of 3.8e-5 would end the first leg a few
    # ulps away from where the uninterrupted run's output times put it, and the steps would differ.
    if LONG:
        rod = SRC / "decks/stretching_rod_damage_2d.toml"
        stopped_and_restarted(rod, 2, tmp / "srd", ["run.end_time=4e-5"], 4300,
                              "stretching rod (ASPH, tensor damage), 2 ranks, restart mid-failure")

    # ASPH in 3D: the shapes come from the Voronoi cells among the step's neighbors (nothing of
    # them is checkpointed), and the kept lists are searched again after the restart.
    stopped_and_restarted(SRC / "decks/taylor_bar_3d.toml", 2, tmp / "asph3d",
                          ["run.resolution=0.4", "run.max_steps=40", "solver.method=asph"], 20,
                          "Taylor bar (ASPH, 3D), 2 ranks, restart")

    # The cap model mid-compaction (saturated): eps_v^p, X, porosity and pore pressure are
    # checkpointed; the return after the restart starts from the same state.
    sand = SRC / "decks/sandstone_confined_2d.toml"
    wet = ["run.resolution=0.5", "material.sandstone.strength.fluid_bulk_modulus=2.2e9"]
    stopped_and_restarted(sand, 2, tmp / "sand", ["run.end_time=1e-5", *wet], 300,
                          "confined sandstone (cap, pore fluid), 2 ranks, restart mid-compaction")
    # ... rate-dependent: the overstress (deviator and I1) is checkpointed with the rest.
    rate = ["run.resolution=0.5", "material.sandstone.strength.rate_t1=1.58e-4",
            "material.sandstone.strength.rate_t2=0.5"]
    stopped_and_restarted(sand, 2, tmp / "sand_rate", ["run.end_time=1e-5", *rate], 300,
                          "confined sandstone (rate-dependent cap), 2 ranks, restart mid-compaction")

    # P-alpha mid-compaction: the distension is checkpointed; the solve after the restart starts
    # from the same alpha_old.
    pumice = SRC / "decks/pumice_impact_2d.toml"
    coarse = ["run.resolution=0.5", "run.end_time=2e-6"]
    stopped_and_restarted(pumice, 2, tmp / "pum", coarse, 80,
                          "pumice impact (P-alpha, flaws), 2 ranks, restart mid-compaction")
    # ... with elastic distension: the plastic distension is checkpointed too.
    elastic = ["run.resolution=0.5", "run.end_time=1.5e-6",
               "material.pumice.porosity.elastic_sound_speed=1000"]
    stopped_and_restarted(pumice, 1, tmp / "pum_el", elastic, 60,
                          "pumice impact with elastic distension, restart mid-compaction")

    # MPM mid-impact: the grid's origin is checkpointed, the grid itself made afresh from the
    # points (their half-widths checkpointed); 2D disks at step 200 of 440 with APIC (each
    # point's velocity gradient C_p, affine_velocity, checkpointed), the 3D Taylor bar against
    # its wall (Johnson-Cook) at step 100.
    stopped_and_restarted(SRC / "decks/two_disks_mpm_2d.toml", 3, tmp / "mpm_disks_apic",
                          ['solver.mpm.transfer="apic"'], 200,
                          "two disks (MPM, APIC), 3 ranks, restart mid-impact")
    stopped_and_restarted(SRC / "decks/glancing_disks_mpm_2d.toml", 3, tmp / "mpm_glancing",
                          ['solver.contact="friction"', "solver.mpm.friction=0.3"], 200,
                          "glancing disks (MPM, Coulomb friction), 3 ranks, restart mid-impact")
    # CPDI: the domains (particle_domain) are checkpointed; the bar stopped at stretch 2.
    stopped_and_restarted(SRC / "decks/stretching_bar_mpm_2d.toml", 3, tmp / "mpm_stretch", [],
                          90, "stretching bar (MPM, CPDI), 3 ranks, restart at stretch 2")
    # ... with the bulk viscosity: q is checkpointed (the grid force and the time step read it);
    # and cpGIMP, whose boxes come from the checkpointed domains.
    stopped_and_restarted(SRC / "decks/taylor_bar_3d.toml", 2, tmp / "mpm_taylor",
                          ["run.resolution=0.4", "run.end_time=1e-5", "solver.method=mpm",
                           "solver.mpm.viscosity={linear=0.2, quadratic=2.0}",
                           'solver.mpm.shape="cpgimp"'], 100,
                          "Taylor bar (MPM, cpGIMP, 3D, bulk viscosity), 2 ranks, restart "
                          "mid-impact")

    # ---- N to M ------------------------------------------------------------------------------
    ckpt = tmp / "half2" / "checkpoints"
    for ranks in (1, 3):
        out = tmp / f"n2m{ranks}"
        (out / "checkpoints").mkdir(parents=True)
        shutil.copy(ckpt / "ckpt_000026.h5", out / "checkpoints")
        (out / "checkpoints" / "latest").write_text("ckpt_000026.h5\n")
        shutil.copytree(tmp / "half2" / "snapshots", out / "snapshots")
        for f in (out / "snapshots").glob("snap_000002*"):
            f.unlink()
        shutil.copy(tmp / "half2" / "history.csv", out / "history.csv")
        run(SHEAR, ranks, out, ["run.end_time=0.1"], restart="latest")
        same_state(tmp / "full2", out, f"2-rank checkpoint restarted on {ranks} rank(s)", 1e-12)
        same_logs(tmp / "full2", out, f"2 -> {ranks} ranks", exact=False)

    # ---- crash: SIGKILL mid-run --------------------------------------------------------------
    long_sets = ["run.end_time=0.5", "checkpoint.every_steps=10"]
    ref = tmp / "long_ref"
    run(SHEAR, 2, ref, ["run.end_time=0.5"])
    crash = tmp / "crash"
    proc = subprocess.Popen(command(SHEAR, 2, crash, long_sets), env=ENV,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    reached = wait_for_checkpoint(crash, 30, proc)
    time.sleep(0.05)  # a few steps past the checkpoint
    kill_all(proc)
    check(reached, "crash: the run was killed after its checkpoint at step >= 30, before its end")
    run(SHEAR, 2, crash, long_sets, restart="latest")
    same_state(ref, crash, "SIGKILL mid-run, restarted from latest")
    same_logs(ref, crash, "SIGKILL mid-run")

    # ---- crash inside a checkpoint write ------------------------------------------------------
    for ranks in (1, 2):
        out = tmp / f"kill_in_write{ranks}"
        p = run(SHEAR, ranks, out, long_sets,
                env=dict(ENV, SPALL_TEST_KILL_IN_CHECKPOINT="3"), expect=None)
        check(p is not None and p.returncode != 0, f"{ranks} rank(s): the writer died mid-checkpoint")
        check(latest(out) == "ckpt_000020.h5" and (out / "checkpoints/ckpt_000030.h5.tmp").exists()
              and not (out / "checkpoints/ckpt_000030.h5").exists(),
              f"{ranks} rank(s): latest still names the last complete checkpoint "
              f"({latest(out)}), the broken one is only a .tmp")
        run(SHEAR, ranks, out, long_sets, restart="latest")
        check(not list((out / "checkpoints").glob("*.tmp")), f"{ranks} rank(s): .tmp cleaned up")
        same_state(ref, out, f"{ranks} rank(s): killed inside a checkpoint write, restarted")
        same_logs(ref, out, f"{ranks} rank(s): killed inside a checkpoint write", exact=ranks == 2)

    # ---- signals -------------------------------------------------------------------------------
    # SIGUSR1 goes to mpirun, which forwards it (as srun does); SIGTERM goes straight to a
    # 1-rank spall, as Slurm sends it to every task at the time limit.
    for ranks, sig in ((2, signal.SIGUSR1), (1, signal.SIGTERM)):
        out = tmp / f"signal{ranks}"
        cmd = command(SHEAR, ranks, out, long_sets)
        cmd.remove("--quiet")
        if ranks == 1:
            cmd = cmd[cmd.index(str(SPALL)):]
        proc = subprocess.Popen(cmd, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                text=True)
        reached = wait_for_checkpoint(out, 20, proc)
        proc.send_signal(sig)  # to mpirun, which forwards it to the ranks
        text, _ = proc.communicate(timeout=TIMEOUT)
        check(reached and proc.returncode == 0,
              f"{sig.name} on {ranks} rank(s): exit {proc.returncode} after a checkpoint")
        check("resume with" in text and "--restart latest" in text,
              f"{sig.name}: the message says how to resume")
        name = latest(out)
        stop_step = int(name[5:-3]) if name else -1
        check(stop_step > 20 and f"stopped by {sig.name} at step {stop_step}:" in text,
              f"{sig.name}: checkpoint written at the stop step {stop_step}")
        run(SHEAR, ranks, out, long_sets, restart="latest")
        same_state(ref, out, f"{sig.name} on {ranks} rank(s), resumed")
        same_logs(ref, out, f"{sig.name} on {ranks} rank(s)", exact=ranks == 2)

    # ---- wall-clock checkpoints and keep ----------------------------------------------------
    # How many checkpoints a wall-clock interval gives depends on the machine's speed: the
    # expectation comes from the run's own wall time. A checkpoint falls due at the first step
    # after each interval (plus the one at the end), so a run of W seconds writes at least
    # floor(W / (interval + longest step + write)) + 1; half of W / interval leaves room for
    # slow steps and writes on a loaded machine and still fails if the interval is ignored.
    out = tmp / "wall"
    run(SHEAR, 2, out, ["run.end_time=2.0", "checkpoint.every_wall_seconds=0.1", "checkpoint.keep=500"])
    kept = sorted((out / "checkpoints").glob("ckpt_*.h5"))
    wall = json.loads((out / "summary.json").read_text())["wall_seconds"]
    expected = max(2, int(0.5 * wall / 0.1))
    check(len(kept) >= expected and latest(out) == kept[-1].name,
          f"every_wall_seconds = 0.1 over a run of {wall:.2f} s: {len(kept)} checkpoints "
          f"(at least {expected}), latest the newest")
    run(SHEAR, 2, out, ["run.end_time=2.5", "checkpoint.every_steps=10", "checkpoint.keep=2"],
        restart="latest")
    kept = sorted((out / "checkpoints").glob("ckpt_*.h5"))
    check(len(kept) == 2, f"keep = 2: {len(kept)} checkpoints left")

    # ---- bad checkpoints -------------------------------------------------------------------
    good = tmp / "half2" / "checkpoints" / "ckpt_000050.h5"
    data = good.read_bytes()
    with h5py.File(good, "r") as f:
        offset = f["particles/velocity"].id.get_offset()
    bad = tmp / "bad"
    bad.mkdir()
    (bad / "truncated.h5").write_bytes(data[: len(data) // 2])
    flipped = bytearray(data)
    flipped[offset + 1000] ^= 0x10
    (bad / "flipped.h5").write_bytes(bytes(flipped))
    (bad / "garbage.h5").write_bytes(os.urandom(4096))
    shutil.copy(good, bad / "version.h5")
    with h5py.File(bad / "version.h5", "r+") as f:
        f.attrs.modify("format_version", 99)
    cases = [("truncated.h5", [], "truncated"), ("flipped.h5", [], "checksum"),
             ("garbage.h5", [], "not a readable HDF5 file"), ("version.h5", [], "format version 99"),
             (good, ["solver.cfl=0.2"], "different deck"), ("missing.h5", [], "no such file")]
    for name, sets, expect in cases:
        path = name if isinstance(name, Path) else bad / name
        out = tmp / f"refused_{Path(name).stem}"
        p = run(SHEAR, 2, out, ["run.end_time=0.1"] + sets, restart=path, expect=2)
        if p is None:
            continue
        check(str(path) in p.stderr and expect in p.stderr,
              f"{Path(name).name}: refused naming the file ('{expect}')")
        check(not out.exists(), f"{Path(name).name}: nothing written")
    p = run(SHEAR, 2, tmp / "nothing_here", [], restart="latest", expect=2)
    check(p is not None and "checkpoints/latest does not exist" in p.stderr,
          "--restart latest with no checkpoint: exit 2 naming the missing latest")

    # A corrupt newest checkpoint: --restart latest falls back to the one before and says so.
    fb = tmp / "fallback"
    run(SHEAR, 2, fb, ["run.end_time=0.1", "checkpoint.every_steps=10", "checkpoint.keep=3"])
    newest = fb / "checkpoints" / latest(fb)
    with h5py.File(newest, "r") as f:
        off = f["particles/position"].id.get_offset()
    b = bytearray(newest.read_bytes())
    b[off + 5] ^= 0x01
    newest.write_bytes(bytes(b))
    cmd = command(SHEAR, 2, fb, ["run.end_time=0.1", "checkpoint.every_steps=10"], "latest")
    cmd.remove("--quiet")
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=TIMEOUT)
    check(p.returncode == 0 and "ckpt_000040.h5" in p.stdout and "checksum" in p.stdout + p.stderr,
          f"corrupt newest checkpoint: fell back to ckpt_000040.h5 and said why (exit {p.returncode})")
    same_state(tmp / "full2", fb, "fallback restart")

    # ---- a target shot again: what has not joined the run yet may change ---------------------
    # The strengthless rod joins at 1 us; the block runs alone to a checkpoint at step 24 (2
    # ranks). Restarted with a slower rod of a lighter alloy (its body's and its material's keys),
    # the run equals that rod's run from t = 0 bit for bit, on 1 and on 3 ranks: nothing before a
    # body joins depends on it. What the checkpoint holds stays refused.
    hydro = SRC / "decks/rod_penetration_hydro_rz.toml"
    waits = ["run.resolution=0.5", "body.rod.insert_time=1e-6", "run.end_time=2e-6"]
    settled = tmp / "settled"
    run(hydro, 2, settled, [*waits, "run.max_steps=24"])
    ckpt = settled / "checkpoints" / (latest(settled) or "none")
    slower = ["body.rod.velocity=[0.0, -2000.0]", "material.tungsten.density=17600"]
    run(hydro, 1, tmp / "shot_fresh", [*waits, *slower])
    for ranks in (1, 3):
        run(hydro, ranks, tmp / f"shot{ranks}", [*waits, *slower], restart=ckpt)
        same_state(tmp / "shot_fresh", tmp / f"shot{ranks}",
                   f"another rod into the checkpointed block, restarted on {ranks} rank(s), "
                   "against that rod's run from t = 0", same_index=False)
    summary = tmp / "shot1" / "summary.json"
    changed = json.loads(summary.read_text())["checkpoint"].get("changed_on_restart") \
        if summary.exists() else None
    check(changed == ["body.rod.velocity: [0, -3000] in the checkpoint, [0, -2000] now",
                      "material.tungsten.density: 19300 in the checkpoint, 17600 now"],
          f"summary.json says what the restart changed: {changed}")
    for label, sets, expect in [
            ("a joined body's key", ["body.target.velocity=[0.0, 1.0]"],
             "body.target.velocity: [0, 0] in the checkpoint, [0, 1] now"),
            ("a joined body's material", ["material.target_metal.density=9000"],
             "material.target_metal.density: 8930 in the checkpoint, 9000 now"),
            ("the rod joining before the checkpoint", ["body.rod.insert_time=2e-7"],
             "rod_penetration_hydro_rz.toml:44:1: error: body 'rod' has not joined the run"),
            # The rod is listed first: its count numbers the block's ids.
            ("a shorter rod before the block",
             ['body.rod.shape={type="box", min=[0.0, 0.0], max=[2.0e-3, 20.0e-3]}'],
             "list the bodies that join later after those present")]:
        out = tmp / f"shot_refused_{len(label)}"
        p = run(hydro, 2, out, [*waits, *sets], restart=ckpt, expect=2)
        check(p is not None and expect in p.stderr and not out.exists(),
              f"restart with {label}: exit 2 saying '{expect}', nothing written")

print(f"\n{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
