#!/usr/bin/python3
"""A particle recorded in a run, replayed by the single-element driver (issue 16; Austin 2013,
Sec. 4.2.1): the run advances each solid particle's deformation gradient with the velocity
gradient its material update uses, F_n+1 = (I + dt L_n) F_n (his Eq. 4.9), and writes the
recorded particles' F every step (particles/particle_ID.ftable) with their stress and state
(particles/particle_ID.csv). `spall history` hands the F-table out; `spall element` on it (one
substep a row, the run's kinematics L = (F_n+1 F_n^-1 - I)/dt, Eq. 4.10, and the recorded density
and energy for the EOS) must give the particle's stress history back to round-off.

Scene: decks/stretching_rod_2d.toml (von Mises copper, ASPH, 300 steps, 2 ranks), a corner
particle (id 0: stretch, shear and spin) and an inner one (777). Tolerance 1e-11 relative to the
largest stress component of the history: L is rebuilt from F through a product and an inverse,
which loses a few digits where L dt is small against F (measured 2e-15; the shear component alone
3e-13 of its own largest value); the pressure comes out
exact (the same EOS call on the same density and energy). Also: `spall history` returns the
recorded table, and from the snapshots alone (a particle not recorded) the recorded rows at
the snapshot times (the snapshots store F row-major; read the other way it is F^T, which the
corner particle's shear tells apart); the recording is the same on 1 and 2 ranks and through a restart (text
identical). And a cap particle (confined sandstone under a piston, saturated; and rate-dependent, its overstress recorded) replayed to
round-off, its plastic volumetric strain, porosity and pore pressure too; and two P-alpha particles
of the pumice impact (distension, and damage from the run's own flaws) to round-off. Each
recording's second half replayed alone (starting from the recorded state, as a failed run's
particle is replayed from its rescue point) gives the same rows. And two cracking particles of
Owen's tensor damage (the stretching rod), whole and from a row where one is already damaged.

usage: test_replay.py SPALL SOURCE_DIR
"""
import csv
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
DECK = SRC / "decks" / "stretching_rod_2d.toml"
IDS = (0, 777)
RECORD = f"output.record_particles=[{', '.join(str(i) for i in IDS)}]"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def spall(args, ranks=1):
    cmd = ([] if ranks == 1 else ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np",
                                   str(ranks)]) + [SPALL] + [str(a) for a in args]
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, stdin=subprocess.DEVNULL)
    if p.returncode != 0:
        check(False, f"{' '.join(cmd)}: exit {p.returncode}\n{p.stderr[-2000:]}")
    return p.returncode == 0


def run(out, ranks, steps, restart=False):
    args = ["run", DECK, "--output", out, "--quiet", "--set", RECORD, "--set",
            f"run.max_steps={steps}"]
    return spall(args + (["--restart", "latest"] if restart else []), ranks)


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


STRESS = ("sxx", "syy", "szz", "sxy", "syz", "sxz")


def stress_error(a, b):
    """The largest difference of b's stress components from a's, relative to a's largest."""
    scale = max(np.max(np.abs(a[c])) for c in STRESS)
    return max(np.max(np.abs(a[c] - b[c])) for c in STRESS) / scale


def from_midway(deck, material, table, state, extra, name):
    """The recording's second half alone: a replay that starts mid-run (as a failed run's, from
    its rescue point) starts from the recorded state (deviatoric stress, plastic strain,
    temperature, a cap's eps_v^p, alpha, damage and flaws) and must give the same rows, to the
    same round-off as the whole replay."""
    lines = [l for l in table.read_text().splitlines() if not l.startswith("#")]
    rows = state.read_text().splitlines()
    k = len(lines) // 2
    half_table, half_state = tmp / f"{name}_half.ftable", tmp / f"{name}_half.csv"
    half_table.write_text("\n".join(lines[k:]) + "\n")
    half_state.write_text("\n".join([rows[0]] + rows[1 + k:]) + "\n")
    out = tmp / f"{name}_half_replay.csv"
    if not spall(["element", deck, "--material", material, "--table", half_table, "--substeps",
                  "1", "--state", half_state, "--output", out, *extra]):
        return
    a, b = read(half_state), read(out)
    worst = stress_error(a, b)
    cols = [c for c in ("plastic_strain", "plastic_volumetric_strain", "porosity_alpha", "damage")
            if c in a and c in b]
    rel = max(np.max(np.abs(a[c] - b[c])) / max(np.max(np.abs(a[c])), 1e-300) for c in cols)
    started = max(abs(a[c][0]) for c in STRESS) > 1e-3 * max(np.max(np.abs(a[c])) for c in STRESS)
    check(np.array_equal(a["t"], b["t"]) and worst < 1e-11 and rel < 1e-11 and started,
          f"{name}: its second half alone (from row {k}, the stress there "
          f"{'set' if started else 'NOT set'}) replays within {worst:.1e} (stress), {rel:.1e} "
          f"({', '.join(cols)}) of the run's")


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    two, one, chain = tmp / "two", tmp / "one", tmp / "chain"
    ok = run(two, 2, 300) and run(one, 1, 300) and run(chain, 1, 150) and run(chain, 1, 300, True)
    if ok:
        for pid in IDS:
            files = [f"particles/particle_{pid}.{ext}" for ext in ("ftable", "csv")]
            check(all((two / f).read_text() == (one / f).read_text() for f in files),
                  f"particle {pid}: the recording on 2 ranks is the one on 1, byte for byte")
            check(all((chain / f).read_text() == (one / f).read_text() for f in files),
                  f"particle {pid}: 150 steps + a restart to 300 record what 300 steps do")
            table = tmp / f"history_{pid}.ftable"
            if not spall(["history", two, "--particle", pid, "--output", table]):
                continue
            strip = lambda p: [l for l in p.read_text().splitlines() if not l.startswith("#")]
            check(strip(table) == strip(two / files[0]),
                  f"particle {pid}: spall history gives the recorded F-table "
                  f"({len(strip(table))} rows)")
            # ... and from the snapshots' deformation_gradient where the particle was not
            # recorded: the recorded rows at the snapshot times, line for line (corner particle 0
            # shears and spins: a transposed F reads differently, checked below).
            bare = tmp / f"bare_{pid}"
            if not bare.exists():
                (bare / "snapshots").mkdir(parents=True)
                for f in (two / "snapshots").iterdir():
                    os.symlink(f, bare / "snapshots" / f.name)
                for f in ("deck.toml", "history.csv"):
                    if (two / f).exists():
                        os.symlink(two / f, bare / f)
            snap_table = tmp / f"snap_history_{pid}.ftable"
            if spall(["history", bare, "--particle", pid, "--output", snap_table]):
                recorded = {l.split()[0]: l for l in strip(two / files[0])}
                rows = strip(snap_table)
                F = np.array([[float(v) for v in l.split()[1:10]] for l in rows]).reshape(-1, 3, 3)
                skew = np.max(np.abs(F - F.transpose(0, 2, 1)))
                check(len(rows) > 1 and all(recorded.get(l.split()[0]) == l for l in rows)
                      and (pid != 0 or skew > 1e-3),
                      f"particle {pid}: spall history from the snapshots alone gives the recorded "
                      f"rows at their {len(rows)} times (F - F^T up to {skew:.1e})")
            out = tmp / f"replay_{pid}.csv"
            if not spall(["element", DECK, "--material", "copper", "--table", table, "--substeps",
                          "1", "--state", two / files[1], "--output", out]):
                continue
            a, b = read(two / files[1]), read(out)
            worst = stress_error(a, b)
            dp = np.max(np.abs(a["pressure"] - b["pressure"]))
            deps = np.max(np.abs(a["plastic_strain"] - b["plastic_strain"]))
            check(len(a["t"]) == len(b["t"]) == 301 and np.array_equal(a["t"], b["t"])
                  and worst < 1e-11 and dp == 0.0 and deps < 1e-12
                  and a["plastic_strain"][-1] > 0.1,
                  f"particle {pid}: replayed stress within {worst:.1e} of the run's (relative, "
                  f"< 1e-11), pressure {'exact' if dp == 0.0 else f'off by {dp:.3g}'}, plastic "
                  f"strain within {deps:.1e} (it reaches {a['plastic_strain'][-1]:.3f})")
            from_midway(DECK, "copper", table, two / files[1], [], f"copper_{pid}")

    # A cap material under a piston's impact (decks/sandstone_confined_2d.toml, saturated): one
    # particle by the piston, one in the middle, recorded over 10 us on 2 ranks, replayed with
    # the run's density (the cap's mean stress is its elastic volume strain). Everything the
    # return computes (stress, eps_v^p, porosity, pore pressure) must come back to round-off.
    sand = SRC / "decks" / "sandstone_confined_2d.toml"
    wet = ["--set", "run.resolution=0.5", "--set",
           "material.sandstone.strength.fluid_bulk_modulus=2.2e9"]
    # ... and rate-dependent (the overstress, deviator and I1, recorded and read back).
    rate = ["--set", "material.sandstone.strength.rate_t1=1.58e-4", "--set",
            "material.sandstone.strength.rate_t2=0.5"]
    for label, sets in (("", wet), ("rate_", wet + rate)):
        out = tmp / f"sand_{label}"
        if not spall(["run", sand, "--output", out, "--quiet", "--set", "run.end_time=1e-5",
                      "--set", "output.record_particles=[790, 410]", *sets], 2):
            continue
        for pid in (790, 410):
            table = out / f"particles/particle_{pid}.ftable"
            state = out / f"particles/particle_{pid}.csv"
            replay = tmp / f"sand_{label}{pid}.csv"
            if not spall(["element", sand, "--material", "sandstone", "--table", table,
                          "--substeps", "1", "--state", state, "--output", replay, *sets]):
                continue
            a, b = read(state), read(replay)
            worst = stress_error(a, b)
            cols = ("plastic_volumetric_strain", "porosity", "pore_pressure", "cap_position")
            rel = max(np.max(np.abs(a[c] - b[c])) / max(np.max(np.abs(a[c])), 1e-300)
                      for c in cols)
            check(np.array_equal(a["t"], b["t"]) and worst < 1e-11 and rel < 1e-11 and
                  a["plastic_volumetric_strain"][-1] < -1e-4 and a["pore_pressure"][-1] > 1e6,
                  f"{label}sandstone particle {pid}: replayed stress within {worst:.1e} of the "
                  f"run's, cap state within {rel:.1e} (relative, < 1e-11); it compacted to "
                  f"eps_v^p = {a['plastic_volumetric_strain'][-1]:.2e}, pore pressure "
                  f"{a['pore_pressure'][-1] / 1e6:.1f} MPa")
            from_midway(sand, "sandstone", table, state, sets, f"sandstone_{label}{pid}")

    # P-alpha with strength and flaws (decks/pumice_impact_2d.toml at half resolution, 2 us, 2
    # ranks): a particle under the projectile that compacts fully, one aside that compacts
    # part-way and cracks, and one that activates flaws past those of its first draw (drawn from
    # its id, which the recording carries). The recording carries the distension and the particle's own flaw draw
    # (count, strain scale, next threshold, active), which the replay starts from.
    # Then the same with elastic distension (elastic_sound_speed: the plastic distension is a
    # recorded state too).
    pumice = SRC / "decks" / "pumice_impact_2d.toml"
    for variant, coarse in (("", ["--set", "run.resolution=0.5"]),
                            (" (elastic distension)", ["--set", "run.resolution=0.5", "--set",
                             "material.pumice.porosity.elastic_sound_speed=1000"])):
        out = tmp / f"pumice{len(variant)}"
        if not spall(["run", pumice, "--output", out, "--quiet", "--set", "run.end_time=2e-6",
                      "--set", "output.record_particles=[3079, 2923, 2679]", *coarse], 2):
            continue
        for pid in (3079, 2923, 2679):
            table, state = out / f"particles/particle_{pid}.ftable", out / f"particles/particle_{pid}.csv"
            replay = tmp / f"pumice{len(variant)}_{pid}.csv"
            if not spall(["element", pumice, "--material", "pumice", "--table", table,
                          "--substeps", "1", "--state", state, "--output", replay, *coarse]):
                continue
            a, b = read(state), read(replay)
            worst = stress_error(a, b)
            dalpha = float(np.max(np.abs(a["porosity_alpha"] - b["porosity_alpha"])))
            dd = float(np.max(np.abs(a["damage"] - b["damage"])))
            check(np.array_equal(a["t"], b["t"]) and worst < 1e-11 and dalpha < 1e-12 and
                  dd < 1e-12 and a["porosity_alpha"][-1] < 2.0,  # compacted: alpha0 = 3
                  f"pumice particle {pid}{variant}: replayed stress within {worst:.1e} of the run's, "
                  f"alpha within {dalpha:.1e}, damage within {dd:.1e}; it compacted to alpha = "
                  f"{a['porosity_alpha'][-1]:.4f}, damage {a['damage'][-1]:.3f}")
            from_midway(pumice, "pumice", table, state, coarse, f"pumice_{pid}{variant}")

    # Owen's tensor damage (decks/stretching_rod_damage_2d.toml, ASPH, 5515 steps, 1 rank): two
    # particles that crack (2 and 4 of 7 flaws). The recording carries the damage and strain
    # tensors and the particle's flaw draw. An undamaged particle of this history replays to 4e-12
    # of its peak stress (F-table precision over 5515 small steps); once cracked, the degradation
    # amplifies that (the damage tensor's axes follow the strain tensor's eigenvectors): measured
    # 6e-9, so 1e-7; the damage itself to round-off (5e-14, so 1e-12). Whole and from row 4000.
    rod = SRC / "decks" / "stretching_rod_damage_2d.toml"
    out = tmp / "rod_damage"
    if spall(["run", rod, "--output", out, "--quiet", "--set",
              "output.record_particles=[100, 190]"]):
        for pid in (100, 190):
            table, state = out / f"particles/particle_{pid}.ftable", out / f"particles/particle_{pid}.csv"
            lines = [l for l in table.read_text().splitlines() if not l.startswith("#")]
            rows = state.read_text().splitlines()
            for k in (0, 4000):
                part_t, part_s = tmp / f"rod_{pid}_{k}.ftable", tmp / f"rod_{pid}_{k}.csv"
                part_t.write_text("\n".join(lines[k:]) + "\n")
                part_s.write_text("\n".join([rows[0]] + rows[1 + k:]) + "\n")
                replay = tmp / f"rod_{pid}_{k}_replay.csv"
                if not spall(["element", rod, "--material", "copper", "--table", part_t,
                              "--substeps", "1", "--state", part_s, "--output", replay]):
                    continue
                a, b = read(part_s), read(replay)
                worst = stress_error(a, b)
                dd = float(np.max(np.abs(a["damage"] - b["damage"])))
                check(np.array_equal(a["t"], b["t"]) and worst < 1e-7 and dd < 1e-12 and
                      a["damage"][-1] > 0.2,
                      f"tensor-damage particle {pid} from row {k} (damage {a['damage'][0]:.3f} "
                      f"there): stress within {worst:.1e} of the run's, damage within {dd:.1e} "
                      f"(it reaches {a['damage'][-1]:.3f})")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
