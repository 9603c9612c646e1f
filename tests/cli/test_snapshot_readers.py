#!/usr/bin/python3
"""Snapshots that other tools open: meshio (Debian's python3-meshio) reads every snapshot .xmf
and series.xmf of a 1D, a plane (MPM, with its grid nodes), an rz and a 3D run (2 ranks) as one
point per particle with every dataset as point data; the values are the HDF5 file's (h5py) and
the series' times the snapshots' own. Where pvpython is installed (tools/bootstrap with
SPALL_WITH_PARAVIEW=1), ParaView's XDMF readers (XDMFReader, Xdmf3ReaderS) read the same counts,
arrays and times; otherwise that part says it is skipped.

usage: test_snapshot_readers.py SPALL SOURCE_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import meshio
import numpy as np

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
failures = []

# (name, deck, ranks, --set overrides, point sets: (xmf suffix, HDF5 group))
RUNS = [
    ("1d", "sod_1d.toml", 1, ["run.max_steps=20"], [("", "particles")]),
    ("plane_mpm", "two_disks_mpm_2d.toml", 1, ["run.max_steps=20", "output.grid=true"],
     [("", "particles"), ("_grid", "grid")]),
    ("rz", "rod_segmented_into_steel_rz.toml", 1, ["run.max_steps=20", "run.resolution=0.3"],
     [("", "particles")]),
    ("3d", "sedov_3d.toml", 2, ["run.max_steps=20", "run.resolution=0.5"], [("", "particles")]),
]


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def run(name, deck, ranks, sets, out):
    cmd = ([] if ranks == 1 else ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np",
                                   str(ranks)]) + [SPALL, "run", str(SRC / "decks" / deck),
                                                   "--output", str(out),
                                                   "--set", "output.every_steps=10"]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, stdin=subprocess.DEVNULL)
    if p.returncode != 0:
        sys.exit(f"{name}: {' '.join(cmd)}: exit {p.returncode}\n{p.stderr[-3000:]}")


def h5(path, group):
    with h5py.File(path, "r") as f:
        return {k: f[group][k][()] for k in f[group]}, float(f.attrs["time"])


def meshio_checks(name, out, suffix, group):
    snaps = sorted((out / "snapshots").glob("snap_??????.h5"))
    for snap in snaps:
        xmf = snap.with_name(snap.stem + suffix + ".xmf")
        fields, _ = h5(snap, group)
        try:
            m = meshio.read(xmf)
        except Exception as e:  # noqa: BLE001 - any reader failure is the finding
            check(False, f"{name}: meshio reads {xmf.name}: {type(e).__name__}: {e}")
            continue
        n = len(fields["position"])
        pos = fields["position"].reshape(n, -1)
        pts = m.points[:, :pos.shape[1]]
        ok = (m.points.shape[0] == n and np.array_equal(pts, pos) and
              np.all(m.points[:, pos.shape[1]:] == 0) and
              [c.type for c in m.cells] == ["vertex"] and len(m.cells[0].data) == n and
              set(m.point_data) == set(fields) and
              all(np.array_equal(m.point_data[k], v) for k, v in fields.items()))
        check(ok, f"{name}: meshio reads {xmf.name}: {n} points, {len(m.point_data)} point "
              f"fields, the HDF5 file's values")
    series = out / "snapshots" / f"series{suffix}.xmf"
    try:
        with meshio.xdmf.TimeSeriesReader(series) as r:
            r.read_points_cells()
            times, same = [], True
            for k in range(r.num_steps):
                t, pd, _ = r.read_data(k)
                fields, time = h5(snaps[k], group)
                times.append(t)
                same &= t == time and np.array_equal(pd["position"], fields["position"])
            check(r.num_steps == len(snaps) and same,
                  f"{name}: meshio's TimeSeriesReader reads {series.name}: {r.num_steps} "
                  f"times, each the snapshot's time and positions")
    except Exception as e:  # noqa: BLE001
        check(False, f"{name}: meshio's TimeSeriesReader reads {series.name}: "
              f"{type(e).__name__}: {e}")


PV_SCRIPT = r"""
import sys
from paraview.simple import XDMFReader, Xdmf3ReaderS
snap, series = sys.argv[1], sys.argv[2]
for kind in ("XDMFReader", "Xdmf3ReaderS"):
    make = XDMFReader if kind == "XDMFReader" else Xdmf3ReaderS
    key = "FileNames" if kind == "XDMFReader" else "FileName"
    r = make(**{key: [snap]})
    r.UpdatePipeline()
    info = r.GetDataInformation()
    print(kind, "snap", info.GetNumberOfPoints(), len(r.PointData.keys()))
    s = make(**{key: [series]})
    times = list(s.TimestepValues)
    s.UpdatePipeline(times[-1])
    print(kind, "series", s.GetDataInformation().GetNumberOfPoints(), len(times))
"""


def paraview_checks(name, out, suffix, group, tmp):
    pv = shutil.which("pvpython")
    if not pv:
        print(f"skip {name}: pvpython is not installed (SPALL_WITH_PARAVIEW=1 tools/bootstrap)")
        return
    script = tmp / "pv_read.py"
    script.write_text(PV_SCRIPT)
    snaps = sorted((out / "snapshots").glob("snap_??????.h5"))
    last = snaps[-1]
    fields, _ = h5(last, group)
    n = len(fields["position"])
    p = subprocess.run([pv, str(script), str(last.with_name(last.stem + suffix + ".xmf")),
                        str(out / "snapshots" / f"series{suffix}.xmf")],
                       capture_output=True, text=True, env=dict(ENV, DISPLAY=""), timeout=600)
    lines = [l.split() for l in p.stdout.splitlines() if l.startswith(("XDMF", "Xdmf3"))]
    for kind in ("XDMFReader", "Xdmf3ReaderS"):
        got = {l[1]: l[2:] for l in lines if l[0] == kind}
        ok = (got.get("snap") == [str(n), str(len(fields))] and
              got.get("series") == [str(n), str(len(snaps))])
        check(ok, f"{name}: ParaView's {kind} reads {n} points and {len(fields)} arrays, and "
              f"{len(snaps)} times from the series (got {got or p.stderr[-500:]})")


with tempfile.TemporaryDirectory() as d:
    tmp = Path(d)
    for name, deck, ranks, sets, sets_of_points in RUNS:
        out = tmp / name
        run(name, deck, ranks, sets, out)
        for suffix, group in sets_of_points:
            meshio_checks(name + suffix, out, suffix, group)
            paraview_checks(name + suffix, out, suffix, group, tmp)
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
