"""Reading spall's output in Python: a run's directory, its snapshots as named numpy arrays with
units and the deck's names, its CSV logs as columns, its deck and summary as dicts.

    import spall
    run = spall.Run("out/rod_into_steel_rz")
    s = run.snapshot(-1)                  # the last snapshot
    s["density"], s.units["density"]      # an array, "kg/m^3"
    s.material_names                      # one name per particle
    run.history["total_energy"]           # history.csv's column
    times, v = run.series("velocity", ids=[0, 17])

Import it with PYTHONPATH=tools/python (or after `cmake --install`). Needs numpy and h5py
(Debian's python3-numpy, python3-h5py); runs with /usr/bin/python3.
"""
from .run import Run
from .snapshot import PointSet, Snapshot
from .table import Table, read_csv

__all__ = ["Run", "Snapshot", "PointSet", "Table", "read_csv"]
