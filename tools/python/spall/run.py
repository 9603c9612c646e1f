"""A run's output directory: snapshots, CSV logs, the deck as run, the summary."""
import json
import re
import tomllib
from pathlib import Path

import numpy as np

from .snapshot import Snapshot
from .table import read_csv


class Run:
    """spall.Run(OUTDIR): .snapshot(i) (i = -1 the last), .snapshots (paths in order),
    .times (the snapshots' times), .history, .probes, .penetration, .fragments (Tables, None
    where the run wrote none), .deck (the deck as run, a dict), .summary (summary.json, a dict,
    None before the run has ended), .series(field, ids)."""

    def __init__(self, outdir):
        self.dir = Path(outdir)
        if not self.dir.is_dir():
            raise FileNotFoundError(f"{self.dir} is not a directory")
        if not (self.dir / "snapshots").is_dir() and not (self.dir / "deck.toml").exists():
            raise FileNotFoundError(f"{self.dir} is not a spall run's output directory "
                                    f"(no deck.toml, no snapshots/)")
        self._times = None

    @property
    def snapshots(self):
        pattern = re.compile(r"snap_(\d+)\.h5$")
        found = []
        for p in (self.dir / "snapshots").glob("snap_*.h5"):
            m = pattern.match(p.name)
            if m:
                found.append((int(m.group(1)), p))
        return [p for _, p in sorted(found)]

    def __len__(self):
        return len(self.snapshots)

    def snapshot(self, i=-1):
        files = self.snapshots
        if not files:
            raise IndexError(f"{self.dir} holds no snapshot")
        return Snapshot(files[i])

    @property
    def times(self):
        if self._times is None:
            import h5py
            self._times = np.array([float(h5py.File(p, "r").attrs["time"])
                                    for p in self.snapshots])
        return self._times

    def at(self, time):
        """The snapshot nearest the given time."""
        return self.snapshot(int(np.argmin(np.abs(self.times - time))))

    def _csv(self, name):
        p = self.dir / name
        return read_csv(p) if p.exists() else None

    @property
    def history(self):
        return self._csv("history.csv")

    @property
    def probes(self):
        return self._csv("probes.csv")

    @property
    def penetration(self):
        return self._csv("penetration.csv")

    @property
    def fragments(self):
        return self._csv("fragments.csv")

    @property
    def deck(self):
        return tomllib.loads((self.dir / "deck.toml").read_text())

    @property
    def summary(self):
        p = self.dir / "summary.json"
        return json.loads(p.read_text()) if p.exists() else None

    def series(self, field, ids=None):
        """(times, values): a field of the given particles (default: those of the first
        snapshot) over every snapshot, values[k, j] for snapshot k and ids[j]; NaN where a
        particle is not in a snapshot (not yet inserted, or eroded)."""
        files = self.snapshots
        if not files:
            raise IndexError(f"{self.dir} holds no snapshot")
        first = Snapshot(files[0])
        ids = first.ids if ids is None else np.asarray(ids, dtype=np.uint64)
        times, out = [], None
        for p in files:
            s = Snapshot(p)
            a = s[field]
            if out is None:
                out = np.full((len(files), len(ids)) + a.shape[1:], np.nan)
            order = np.argsort(s.ids, kind="stable")
            at = np.searchsorted(s.ids[order], ids)
            ok = at < len(order)
            ok[ok] = s.ids[order][at[ok]] == ids[ok]
            out[len(times)][ok] = a[order[at[ok]]]
            times.append(s.time)
        return np.array(times), out

    def __repr__(self):
        return f"Run({self.dir}: {len(self)} snapshots)"
