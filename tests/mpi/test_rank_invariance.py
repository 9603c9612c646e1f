#!/usr/bin/python3
"""Whole decks on 1, 2, 3 and 4 ranks (MPM decks on 1, 2, 3 and 5; 3 and more oversubscribed:
correctness only) give the same particle state, matched by id, bit for bit: spall adds every
neighbor sum and every grid node's sum in a canonical order (decomposition.reproducible, on by
default), so the decomposition cannot change a single bit. Also: the 10 km/s stream decks (SPH
on 4 ranks, MPM on 5) cross >= 3 rank domains in one step without losing a particle, global
conservation is the 1-rank run's, and more ranks than particles still runs.

In the fast suite every case runs on 1 and 3 ranks (3: an interior rank with two neighbours, and
oversubscribed), but those the neighbor-skin test also runs on 1 and 3 ranks (IN_SKIN_TEST); with
the third argument `long` every case, on 2 and 4 (MPM 5) ranks too.

usage: test_rank_invariance.py SPALL SOURCE_DIR [long]
"""
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verification"))
from spalltest import Checks, concurrently, final_state  # noqa: E402

SPALL, SRC = Path(sys.argv[1]), Path(sys.argv[2])
LONG = len(sys.argv) > 3 and sys.argv[3] == "long"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
checks = Checks()
check, failures = checks.check, checks.failures


# Runs done ahead of the comparisons, side by side: output directory -> summary.
DONE = {}


def run(deck, ranks, out, *sets):
    if str(out) in DONE:
        return DONE.pop(str(out))
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), str(SPALL), "run",
           str(deck), "--output", str(out), "--overwrite", "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
    if p.returncode != 0:
        failures.append(f"{deck.name} on {ranks} ranks: exit {p.returncode}\n{p.stderr[-2000:]}")
        return None
    return json.loads((out / "summary.json").read_text())


# Shortened where the full run is long: the point is the rank count, not the physics.
CASES = [("sod_1d.toml", []), ("rod_impact_copper.toml", ["run.end_time=6e-6"]),
         ("noh_2d.toml", ["run.end_time=0.05", "run.resolution=0.5"]),
         # ASPH: H travels with the halo; aspect ratios up to ~4 in the converging flow
         ("noh_2d.toml", ["run.end_time=0.05", "run.resolution=0.5", "solver.method=asph"]),
         # Balsara: div v and curl v of the last loop travel with the halo; the loop must not
         # read this loop's values of owned neighbors (it did, and 3 ranks differed from 1)
         ("noh_2d.toml", ["run.end_time=0.05", "run.resolution=0.5",
                          "solver.artificial_viscosity.balsara=true"]),
         # ASPH with elongated ellipses (aspect ratio ~1.7 by 5 us): ghosts and neighbors by their
         # bounding boxes, the kernel correction B through the halo
         ("stretching_rod_2d.toml", ["run.end_time=5e-6"]),
         ("periodic_shear_2d.toml", []),
         # strength: the deviatoric stress travels with the halo and is mirrored at walls
         # (to 2.5 us, 416 of the 1000 particles plastic: its 1476 steps on 3 oversubscribed
         # ranks are mostly waits, ~15 s in CI)
         ("rod_impact_copper_strength.toml", ["run.end_time=2.5e-6",
                                              "body.striker.velocity=[200.0]"]),
         ("taylor_bar_3d.toml", ["run.resolution=0.4", "run.max_steps=20"]),
         # ASPH in 3D: ellipsoids against the rigid wall (mirrored H) and across ranks
         ("taylor_bar_3d.toml", ["run.resolution=0.4", "run.max_steps=20", "solver.method=asph"]),
         # cuts from measured times (decomposition.cost = "timed"), a new partition every 5
         # steps that no other run repeats: the physics must not see it
         ("taylor_bar_3d.toml", ["run.resolution=0.4", "run.max_steps=30",
                                 'decomposition.cost="timed"', "decomposition.rebalance_every=5"]),
         # axisymmetric: the axis images (and the wall's images of them), ring masses, hoop
         # terms; SPH and ASPH
         ("taylor_bar_rz.toml", ["run.end_time=1e-5"]),
         ("taylor_bar_rz.toml", ["run.end_time=6e-6", "solver.method=asph"]),
         # Zerilli-Armstrong: its return (the plastic rate found with the yield stress) and the
         # temperature it reads
         ("taylor_bar_za_rz.toml", ["run.end_time=1e-5"]),
         # damage: flaws from (seed, id), damage through the halo, failed pairs, mid-spall
         ("spall_plate_1d.toml", ["run.end_time=2.2e-6"]),
         # 2D damage and fragments: `fragment` (friends of friends across ranks) bit for bit
         ("rock_impact_2d.toml", ["run.end_time=4e-6"]),
         # Owen's tensor damage: the damage and strain tensors, eigen-decompositions per particle
         ("rock_impact_2d.toml", ["run.end_time=3e-6", 'material.basalt.damage.mode="tensor"']),
         # ASPH with tensor damage mid-failure: cracked pairs (a failed particle between two
         # intact ones) decided alike whichever rank owns the three
         # (fast: pulled twice as fast, to 20 us, 22 of the 800 failed and 642 damaged; long: as
         # shipped, to 40 us)
         ("stretching_rod_damage_2d.toml", ["run.end_time=4e-5"] if LONG else [
             "run.end_time=2e-5",
             "body.rod.linear_velocity={center=[0.0,0.0],gradient=[[1.0e5,0.0],[0.0,-1.0e5]]}"]),
         # the cap model (saturated): a confined block crushing behind a piston, walls, a
         # Brent-iterated return per particle; plastic volumetric strain, cap, pore pressure
         ("sandstone_confined_2d.toml", ["run.end_time=8e-6", "run.resolution=0.5",
                                         "material.sandstone.strength.fluid_bulk_modulus=2.2e9"]),
         # ... rate-dependent (Duvaut-Lions): the overstress, a per-particle history
         ("sandstone_confined_2d.toml", ["run.end_time=8e-6", "run.resolution=0.5",
                                         "material.sandstone.strength.rate_t1=1.58e-4",
                                         "material.sandstone.strength.rate_t2=0.5"]),
         # P-alpha with strength and flaws: the distension compacting by a Newton solve per
         # particle behind a 2.58 km/s projectile
         ("pumice_impact_2d.toml", ["run.end_time=1.5e-6", "run.resolution=0.5"]),
         # ... with elastic distension (Herrmann): an elastic trial solve, then the plastic one
         ("pumice_impact_2d.toml", ["run.end_time=1.0e-6", "run.resolution=0.5",
                                    "material.pumice.porosity.elastic_sound_speed=1000"]),
         # MPM: every grid node sums its points in id order on whichever ranks hold them; 1D with
         # a wall node, 2D through the disks' impact, 3D with Johnson-Cook against the wall
         ("vibrating_bar_mpm_1d.toml", ["run.end_time=10"]),
         # ... the disks with APIC: each point's velocity gradient C_p to its ghosts, in the P2G
         # and the remap
         ("two_disks_mpm_2d.toml", ['solver.mpm.transfer="apic"']),
         # ... frictionless contact: a velocity field per disk, the contact at each node summed
         # over its fields in field order
         ("glancing_disks_mpm_2d.toml", ["run.end_time=2.5"]),
         # ... with APIC: the affine part at each (node, field) pair's place
         ("glancing_disks_mpm_2d.toml", ["run.end_time=2.5", 'solver.mpm.transfer="apic"']),
         # ... Coulomb friction against a fixed body under a load: the friction's heat from
         # each (node, field) pair to its points
         ("sliding_block_friction_mpm_2d.toml", ["run.end_time=1.2e-5"]),
         # ... uGIMP: each point's box as made
         ("taylor_bar_3d.toml", ["run.resolution=0.4", "run.max_steps=40", "solver.method=mpm",
                                 'solver.mpm.shape="gimp"']),
         # ... cpGIMP (the default): each point's box from its domain, the domain to its ghosts
         ("taylor_bar_3d.toml", ["run.resolution=0.4", "run.max_steps=40", "solver.method=mpm"]),
         # ... CPDI: each point's nodes those of its domain's corners, the halo as wide as the
         # most stretched domain reaches (the bar to 2.5x its length, points 1.25 cells apart)
         ("stretching_bar_mpm_2d.toml", ["run.end_time=0.015"]),
         # ... plastic, to failure: Johnson-Cook damage and zero-stress erosion per point
         ("stretching_bar_damage_mpm_2d.toml", ["run.end_time=0.012"]),
         # ... and in rz: the axis a constrained node plane, the hoop terms, the bulk viscosity,
         # the wall's friction and its heat
         ("taylor_bar_4340_rz.toml", ["run.end_time=2e-5", "solver.method=mpm",
                                      "solver.mpm.viscosity={linear=0.2, quadratic=2.0}",
                                      "boundary.1.friction=0.3"]),
         # ... and with APIC: C_p folded with the rings that cross the axis
         ("taylor_bar_4340_rz.toml", ["run.end_time=2e-5", "solver.method=mpm",
                                      'solver.mpm.transfer="apic"']),
         # ... with bodies joining (a [[jet]]'s segments): the grid's origin stays where t = 0
         # put it on every rank, including ranks that hold nothing when a segment joins; and with
         # a velocity field per body (frictionless): a segment's field joins the nodes' lists
         ("rod_segmented_into_steel_rz.toml", ["run.resolution=0.5", "run.end_time=1.5e-5",
                                               "solver.method=mpm"]),
         ("rod_segmented_into_steel_rz.toml", ["run.resolution=0.5", "run.end_time=1.5e-5",
                                               "solver.method=mpm", "solver.contact=frictionless"])]

# Cases whose 1- and 3-rank runs tests/mpi/test_neighbor_skin.py compares too, bit for bit, final
# state and history (skin 0 on 1 rank against skin 0.3 on 3): in the fast suite that test guards
# their rank count; `long` runs them here on 1 to 4 ranks.
IN_SKIN_TEST = {("sod_1d.toml", ()), ("periodic_shear_2d.toml", ()),
                ("noh_2d.toml", ("run.end_time=0.05", "run.resolution=0.5", "solver.method=asph")),
                ("taylor_bar_3d.toml", ("run.resolution=0.4", "run.max_steps=20")),
                ("taylor_bar_3d.toml", ("run.resolution=0.4", "run.max_steps=20",
                                        "solver.method=asph")),
                ("taylor_bar_rz.toml", ("run.end_time=1e-5",)),
                ("rock_impact_2d.toml", ("run.end_time=3e-6", 'material.basalt.damage.mode="tensor"')),
                ("pumice_impact_2d.toml", ("run.end_time=1.5e-6", "run.resolution=0.5"))}

# Space probes (a Shepard-weighted kernel sum over the particles that cover a point) and material
# probes, added to two decks: probes.csv the same text on any rank count.
PROBES = {"noh_2d.toml": """
[[probe]]
name = "shock"
position = [0.13, 0.05]
track = "space"
fields = ["density", "velocity_x", "pressure"]
""", "taylor_bar_3d.toml": """
[[probe]]
name = "face"
position = [1.5e-3, 0.5e-3, 0.5e-3]
track = "space"
fields = ["stress_zz", "velocity_z", "plastic_strain"]

[[probe]]
name = "edge"
position = [3.7e-3, 0.0, 0.2e-3]
track = "material"
fields = ["position_x", "stress_xx"]
"""}

with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    for deck, extra in PROBES.items():
        probed = tmp / deck.replace(".toml", "_probed.toml")
        probed.write_text((SRC / "decks" / deck).read_text() + extra)
    CASES += [(Path(tmp / "noh_2d_probed.toml"), ["run.end_time=0.05", "run.resolution=0.5"]),
              (Path(tmp / "taylor_bar_3d_probed.toml"),
               ["run.resolution=0.4", "run.max_steps=40"])]
    def case_runs(deck, sets):
        """(ranks, deck's path, output) of each run of a case."""
        name = deck.name if isinstance(deck, Path) else deck
        mpm = "_mpm_" in name or "solver.method=mpm" in sets
        path = deck if isinstance(deck, Path) else SRC / "decks" / deck
        if not path.exists():
            path = SRC / "tests" / "mpi" / "decks" / deck
        counts = ((1, 2, 3, 5) if mpm else (1, 2, 3, 4)) if LONG else (1, 3)
        return [(ranks, path, tmp / f"{name}_{len(sets)}_{'_'.join(sets)[-20:]}_{ranks}".replace(
            "/", "_")) for ranks in counts]

    cases = [(d, s) for d, s in CASES if LONG or (d, tuple(s)) not in IN_SKIN_TEST]
    # Every run ahead of the comparisons, the single-rank ones first and two at a time (one core
    # each), then the rest one by one.
    jobs = sorted(((r, p, o, s) for d, s in cases for r, p, o in case_runs(d, s)),
                  key=lambda j: j[0] > 1)
    assert len({str(j[2]) for j in jobs}) == len(jobs), "two runs share an output directory"
    for (ranks, path, out, sets), summary in zip(jobs, concurrently(
            [(r, lambda r=r, p=p, o=o, s=s: run(p, r, o, *s)) for r, p, o, s in jobs])):
        DONE[str(out)] = summary
    for deck, sets in cases:
        base, base_time, base_out = None, None, None
        history = {}
        options = [s.split(".", 1)[1] for s in sets if s.startswith("solver.")]
        name = deck.name if isinstance(deck, Path) else deck
        label = name + (f" ({', '.join(options)})" if options else "")
        for ranks, path, out in case_runs(deck, sets):
            summary = run(path, ranks, out, *sets)
            if summary is None:
                continue
            state, t = final_state(out)
            history[ranks] = np.genfromtxt(out / "history.csv", delimiter=",", names=True)
            if ranks == 1:
                base, base_time, base_out = state, t, out
                continue
            same = t == base_time and set(state) == set(base) and all(
                state[k].shape == base[k].shape and np.array_equal(state[k], base[k]) for k in base)
            worst = 0.0
            if not same and all(state[k].shape == base[k].shape for k in base):
                for k in base:
                    a, b = base[k].astype(float), state[k].astype(float)
                    scale = np.max(np.abs(a)) or 1.0
                    worst = max(worst, float(np.max(np.abs(a - b))) / scale)
            check(same, f"{label} on {ranks} ranks: final state bit-for-bit equal to 1 rank"
                        + ("" if same else f" (largest relative difference {worst:.2e})"))
            # Global conservation: the same totals as on one rank, bit for bit (order-free sums of
            # the same particles).
            h1, hr = history[1], history[ranks]
            for col in ("mass", "momentum_x", "total_energy"):
                scale = max(np.max(np.abs(h1[col])), np.max(np.abs(h1["kinetic_energy"])), 1e-300)
                err = float(np.max(np.abs(h1[col] - hr[col]))) / scale
                check(np.array_equal(h1[col], hr[col]),
                      f"{label} on {ranks} ranks: history {col} identical to 1 rank's ({err:.1e})")
            # Probes, the penetration gauge and the fragment catalogue: the same text as on one
            # rank.
            for csv in ("probes.csv", "penetration.csv", "fragments.csv"):
                if base_out is not None and (base_out / csv).exists():
                    check((out / csv).exists() and
                          (out / csv).read_text() == (base_out / csv).read_text(),
                          f"{label} on {ranks} ranks: {csv} identical to 1 rank's")

    # Fast particles: 10 km/s across >= 3 domains in one step, SPH on 4 ranks and MPM on 5.
    for deck, ranks in (("fast_stream_2d.toml", 4), ("fast_stream_mpm_2d.toml", 5)):
        stream = SRC / "tests" / "mpi" / "decks" / deck
        one, many = tmp / f"{deck}_1", tmp / f"{deck}_{ranks}"
        s1, sn = run(stream, 1, one), run(stream, ranks, many)
        if not (s1 and sn):
            continue
        distance = sn["decomposition"]["max_rank_distance"]
        check(distance >= 3, f"{deck}: crossed {distance} rank domains in one step (>= 3)")
        a, _ = final_state(one)
        b, _ = final_state(many)
        check(np.array_equal(a["id"], b["id"]) and len(np.unique(b["id"])) == len(b["id"]),
              f"{deck}: the same {len(a['id'])} unique ids on {ranks} ranks as on 1")
        h = np.genfromtxt(many / "history.csv", delimiter=",", names=True)
        check(np.all(h["particles"] == h["particles"][0]), f"{deck}: particle count constant")
        check(np.all(h["mass"] == h["mass"][0]), f"{deck}: total mass exactly constant")
        p0 = np.abs(h["momentum_x"][0])
        check(np.max(np.abs(h["momentum_x"] - h["momentum_x"][0])) <= 1e-12 * p0,
              f"{deck}: x momentum constant to 1e-12")
        check(all(np.array_equal(a[k], b[k]) for k in a),
              f"{deck}: final state bit-for-bit as 1 rank")
        # The stream kept its speed, so it did travel the distance the crossing needs (MPM: its
        # own velocity field, the contact tangential). Its own pressure (20 Pa on 4 particles of
        # 2.5e-3 kg/m) changes its speed by ~1 m/s over the run: 10 km/s within 1e-3.
        fast = b["velocity"][:, 0] > 1e3
        check(fast.sum() == 4 and np.allclose(b["velocity"][fast, 0], 1e4, rtol=1e-3),
              f"{deck}: the 4 stream particles still at 10 km/s")

    # More ranks than particles: a 3-particle deck on 4 ranks.
    tiny = tmp / "tiny.toml"
    tiny.write_text((SRC / "decks" / "sod_1d.toml").read_text())
    s = run(tiny, 4, tmp / "tiny4", "body.left.shape.min=[-0.0025]", "body.right.shape.max=[0.01]",
            "run.end_time=0.01")
    s1 = run(tiny, 1, tmp / "tiny1", "body.left.shape.min=[-0.0025]", "body.right.shape.max=[0.01]",
             "run.end_time=0.01")
    if s and s1:
        check(s["particles"] == s1["particles"] and s["particles"] < 4,
              f"{s['particles']} particles on 4 ranks run like on 1")
        a, _ = final_state(tmp / "tiny1")
        b, _ = final_state(tmp / "tiny4")
        check(all(np.array_equal(a[k], b[k]) for k in a), "tiny deck: 4 ranks bit-for-bit as 1 rank")

checks.finish()
