#!/usr/bin/python3
"""MPM's background grid in snapshots (`output.grid = true`: /grid in every snapshot .h5, its
nodes in snap_NNNNNN_grid.xmf beside the particles' .xmf, and series_grid.xmf over time).

Scenes: the colliding disks with a velocity field per disk (2D, GIMP; nodes where both fields
meet), the Taylor bar in 3D with the tent (linear) shape, and the 4340 Taylor bar in rz with CPDI.
Each on 1 and 3 ranks, and through a restart:

1. Every node once: no lattice index twice in a file, and place = origin + index cell_size.
2. The grid against the particles it sums, by the weights' partition of unity (sum_I S_Ip = 1,
   sum_I grad S_Ip = 0) and linear completeness (sum_I S_Ip X_I = x_p), in every snapshot:
   total mass, momentum and mass-weighted centroid equal the particles' (relative 1e-12: the sums
   regroup ~1e5 terms of either sign, a few hundred ulps at worst); the stress forces sum to zero
   (relative to sum |f_I|, 1e-12; in rz only along z: the hoop stress pushes the rings radially).
3. The same nodes and values bit for bit on 1 and 3 ranks, and when the run is restarted from a
   checkpoint halfway (the grid is made from the state alone).
4. `output.grid = true` with SPH: exit 2, the deck's position named, nothing written.

usage: test_mpm_grid_output.py SPALL SOURCE_DIR
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

SRC = Path(sys.argv[2])
sys.path.insert(0, str(SRC / "tests/verification"))
from spalltest import Checks  # noqa: E402

t = Checks()
DECKS = SRC / "decks"

SCENES = [
    ("disks_2d_gimp", DECKS / "two_disks_mpm_2d.toml", 2,
     ["run.end_time=1.6", "solver.contact=frictionless", "output.every=0.4"], 0.8),
    ("taylor_3d_linear", DECKS / "taylor_bar_3d.toml", 3,
     ["run.resolution=0.4", "run.end_time=8e-6", "output.every=2e-6", "solver.method=mpm",
      'solver.mpm.shape="linear"'], 4e-6),
    ("taylor_rz_cpdi", DECKS / "taylor_bar_4340_rz.toml", 2,
     ["run.end_time=2e-5", "output.every=5e-6", "solver.method=mpm", 'solver.mpm.shape="cpdi"',
      "solver.mpm.viscosity={linear=0.2, quadratic=2.0}"], 1e-5),
]


def snapshots(out):
    return sorted((out / "snapshots").glob("snap_*.h5"))


def grid(path):
    """/grid sorted by lattice index, and /particles."""
    with h5py.File(path, "r") as f:
        g = {k: f["grid"][k][()] for k in f["grid"]}
        p = {k: f["particles"][k][()] for k in f["particles"]}
        time = float(f.attrs["time"])
    order = np.lexsort(g["index"].T[::-1])
    return {k: v[order] for k, v in g.items()}, p, time


def identical(a, b):
    return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


def relative(a, b, scale):
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) / scale


def check_sums(name, path, rz):
    g, p, time = grid(path)
    at = f"{name} t={time:.3g}"
    idx = g["index"]
    t.check(len(np.unique(idx, axis=0)) == len(idx), f"{at}: {len(idx)} nodes, each once")
    # The lattice: X - index cell_size is one point (the origin) for every node.
    steps = np.diff(np.unique(g["position"][:, 0]))
    hc = float(np.min(steps)) if len(steps) else 1.0
    origin = g["position"] - idx * hc
    t.check(relative(origin, origin[0], hc) < 1e-9, f"{at}: every node at origin + index cell_size")
    M, m = float(p["mass"].sum()), g["mass"]
    t.check(abs(m.sum() / M - 1.0) < 1e-12, f"{at}: node mass sums to the particles' "
            f"({m.sum() / M - 1.0:.1e})")
    mv_p = (p["mass"][:, None] * p["velocity"]).sum(0)
    mv_g = (m[:, None] * g["velocity"]).sum(0)
    scale = float(np.abs(p["mass"][:, None] * p["velocity"]).sum()) or 1.0
    t.check(relative(mv_g, mv_p, scale) < 1e-12,
            f"{at}: node momentum sums to the particles' ({relative(mv_g, mv_p, scale):.1e})")
    mx_p = (p["mass"][:, None] * p["position"]).sum(0) / M
    mx_g = (m[:, None] * g["position"]).sum(0) / m.sum()
    extent = float(np.ptp(p["position"], axis=0).max())
    t.check(relative(mx_g, mx_p, extent) < 1e-12,
            f"{at}: the nodes' centroid is the particles' ({relative(mx_g, mx_p, extent):.1e})")
    f = g["force"][:, 1:] if rz else g["force"]
    fscale = float(np.abs(f).sum())
    if fscale > 0.0:
        t.check(float(np.abs(f.sum(0)).max()) / fscale < 1e-12,
                f"{at}: stress forces sum to zero{' along z' if rz else ''} "
                f"({float(np.abs(f.sum(0)).max()) / fscale:.1e} of sum |f|)")
    return g


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    for name, deck, dim, sets, half in SCENES:
        sets = sets + ["output.grid=true"]
        one, three = tmp / f"{name}_np1", tmp / f"{name}_np3"
        if not (t.run(deck, one, *sets, ranks=1) and t.run(deck, three, *sets, ranks=3)):
            continue
        rz = "_rz" in name
        for path in snapshots(one) + snapshots(three):
            check_sums(f"{name} {path.parent.parent.name[-3:]}", path, rz)
        if name.startswith("disks"):
            fields = max(int(grid(s)[0]["fields"].max()) for s in snapshots(one))
            t.check(fields == 2, f"{name}: both disks' velocity fields meet at some nodes")
        for a, b in zip(snapshots(one), snapshots(three)):
            t.check(identical(grid(a)[0], grid(b)[0]), f"{name} {a.name}: 1 and 3 ranks bit for bit")
        t.check(len(snapshots(one)) == len(snapshots(three)) >= 3, f"{name}: snapshots on both")
        # Restart: the first half with a checkpoint at its end, then the rest from it.
        chain = tmp / f"{name}_chain"
        end = [s for s in sets if s.startswith("run.end_time")][0]
        first = [s for s in sets if s != end] + [f"run.end_time={half}"]
        if t.run(deck, chain, *first, ranks=2) and \
                t.run(deck, chain, *sets, ranks=3, restart="latest"):
            t.check(identical(grid(snapshots(chain)[-1])[0], grid(snapshots(one)[-1])[0]),
                    f"{name}: restarted halfway (2 then 3 ranks): the last grid bit for bit")
        last = snapshots(one)[-1]
        xmf = last.with_name(last.stem + "_grid.xmf").read_text()
        series = (last.parent / "series_grid.xmf").read_text()
        t.check(":/grid/velocity" in xmf and ":/xdmf/grid_vertices" in xmf and
                f'NumberOfElements="{len(grid(last)[0]["mass"])}"' in xmf and
                series.count("<Time ") == len(snapshots(one)) and
                ":/grid/" not in last.with_suffix(".xmf").read_text(),
                f"{name}: the nodes in {last.stem}_grid.xmf and series_grid.xmf, one grid a time")

    # SPH has no grid: a deck error at the key.
    out = tmp / "sph"
    p = subprocess.run([sys.argv[1], "run", str(DECKS / "sod_1d.toml"), "--output", str(out),
                        "--set", "output.grid=true"],
                       capture_output=True, text=True)
    t.check(p.returncode == 2 and "output.grid" in p.stderr and "mpm" in p.stderr and
            not out.exists(), f"output.grid with SPH: exit {p.returncode}, {p.stderr.strip()[:160]}")
t.finish()
