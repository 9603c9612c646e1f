"""A snapshot file (snapshots/snap_NNNNNN.h5): its particles, or MPM's grid nodes, as named
numpy arrays. The layout is docs/reference.md's "Snapshot HDF5"."""
from pathlib import Path

import h5py
import numpy as np


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def _names(attrs, key):
    if key not in attrs:
        return []
    value = attrs[key]
    if isinstance(value, h5py.Empty):
        return []
    return [_text(v) for v in np.atleast_1d(value)]


class PointSet:
    """One group of rows: /particles or /grid. ps["velocity"] is an [N, dim] array; tensors are
    [N, n, n] with T[i, a, b] the (a, b) component, whatever the file's age."""

    def __init__(self, path, group):
        self.path = Path(path)
        self.group = group
        self._cache = {}
        with h5py.File(self.path, "r") as f:
            if group not in f:
                raise KeyError(f"{self.path} has no /{group}")
            g = f[group]
            self.fields = sorted(g.keys())
            self.units = {k: _text(g[k].attrs["units"]) for k in self.fields
                          if "units" in g[k].attrs}
            self._row_major = {k: _text(g[k].attrs.get("layout", "")) == "row-major"
                               for k in self.fields}
            self.count = g[self.fields[0]].shape[0] if self.fields else 0

    def __len__(self):
        return self.count

    def __contains__(self, name):
        return name in self.fields

    def __iter__(self):
        return iter(self.fields)

    def __getitem__(self, name):
        if name not in self._cache:
            if name not in self.fields:
                raise KeyError(f"{self.path}: /{self.group} has no field '{name}' "
                               f"(fields: {', '.join(self.fields)})")
            with h5py.File(self.path, "r") as f:
                a = f[self.group][name][()]
            # Files from before the `layout` attribute hold Eigen's column-major tensors.
            if a.ndim == 3 and a.shape[1] == a.shape[2] and a.shape[1] > 1 \
                    and a.dtype.kind == "f" and not self._row_major[name]:
                a = np.ascontiguousarray(np.swapaxes(a, 1, 2))
            self._cache[name] = a
        return self._cache[name]

    def unit(self, name):
        """The field's SI unit ("1" for a pure number), "" where the file does not say."""
        return self.units.get(name, "")


class Snapshot(PointSet):
    """A snapshot's particles, with the file's description:
    .time, .step, .dimension, .geometry ("1d", "plane", "rz", "3d"), .axes ("r z", ...),
    .units (field -> unit), .materials and .bodies (index -> deck name), .material_names and
    .body_names (one per particle), .grid (MPM's nodes, a PointSet, or None)."""

    def __init__(self, path):
        super().__init__(path, "particles")
        with h5py.File(self.path, "r") as f:
            a = f.attrs
            self.time = float(a["time"])
            self.step = int(a["step"])
            self.dimension = int(a["dimension"])
            self.version = _text(a.get("spall_version", ""))
            default = {1: "1d", 2: "plane", 3: "3d"}[self.dimension]
            self.geometry = _text(a["geometry"]) if "geometry" in a else default
            self.axes = _text(a["axes"]) if "axes" in a else " ".join("xyz"[:self.dimension])
            self.materials = _names(a, "material_names")
            self.bodies = _names(a, "body_names")
            self._has_grid = "grid" in f
        self._grid = None

    def _per_particle(self, index_field, names):
        index = self[index_field]
        if not names:
            raise KeyError(f"{self.path} does not record the {index_field} names "
                           f"(written before they were)")
        return np.array(names, dtype=object)[index]

    @property
    def material_names(self):
        return self._per_particle("material", self.materials)

    @property
    def body_names(self):
        return self._per_particle("body", self.bodies)

    @property
    def ids(self):
        return self["id"]

    def rows(self, ids):
        """The rows of the given particle ids (KeyError naming an id not in the snapshot)."""
        order = np.argsort(self.ids, kind="stable")
        ids = np.asarray(ids, dtype=np.uint64)
        at = np.searchsorted(self.ids[order], ids)
        at = np.minimum(at, len(order) - 1) if len(order) else at
        if len(order) == 0 or np.any(self.ids[order][at] != ids):
            missing = [int(i) for i in ids if i not in set(self.ids.tolist())]
            raise KeyError(f"{self.path}: no particle with id {missing[0]}")
        return order[at]

    @property
    def grid(self):
        if self._grid is None and self._has_grid:
            self._grid = PointSet(self.path, "grid")
        return self._grid

    def __repr__(self):
        return (f"Snapshot({self.path.name}: t = {self.time:.6g} s, step {self.step}, "
                f"{self.count} particles, {self.geometry})")
