"""A CSV log (history.csv, probes.csv, penetration.csv, fragments.csv) as named columns."""
import csv
from pathlib import Path

import numpy as np


class Table:
    """Columns by name: t["time"] is a numpy array (float, int where every entry is an integer
    literal, str where a value is not a number). len(t) is the row count."""

    def __init__(self, columns, path=None):
        self.columns = dict(columns)
        self.path = path

    def __getitem__(self, name):
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f"{self.path or 'table'} has no column '{name}' "
                           f"(columns: {', '.join(self.columns)})") from None

    def __contains__(self, name):
        return name in self.columns

    def __len__(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def __iter__(self):
        return iter(self.columns)

    def names(self):
        return list(self.columns)

    def where(self, **equal):
        """The rows whose columns equal the given values: probes.where(probe="tip")."""
        keep = np.ones(len(self), dtype=bool)
        for name, value in equal.items():
            keep &= self[name] == value
        return Table({k: v[keep] for k, v in self.columns.items()}, self.path)

    def __repr__(self):
        return f"Table({self.path or ''}: {len(self)} rows of {', '.join(self.columns)})"


def _column(values):
    try:
        ints = [int(v) for v in values]
        if all(v.strip().lstrip("+-").isdigit() for v in values):
            return np.array(ints, dtype=np.int64)
    except ValueError:
        pass
    try:
        return np.array([float(v) for v in values], dtype=float)
    except ValueError:
        return np.array(values, dtype=str)


def read_csv(path):
    """A CSV file with a header row as a Table. A file with a header alone gives empty columns."""
    path = Path(path)
    with open(path, newline="") as f:
        reader = csv.reader(f)
        try:
            header = next(reader)
        except StopIteration:
            raise ValueError(f"{path}: empty file, no header") from None
        rows = [r for r in reader if r]
    for k, r in enumerate(rows):
        if len(r) != len(header):
            raise ValueError(f"{path}:{k + 2}: {len(r)} values, the header has {len(header)}")
    cols = {}
    for j, name in enumerate(header):
        values = [r[j] for r in rows]
        cols[name] = _column(values) if values else np.array([], dtype=float)
    return Table(cols, path)
