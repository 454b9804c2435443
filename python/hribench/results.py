"""Results of a run as data (docs/python.md): hribench.load_results(DIR) reads DIR/results.json
(checked by the C++ reader, eval/report.h) into one row per episode."""

import json

from . import _hribench

try:  # pragma: no cover - depends on the environment
    import pandas as _pandas
except ImportError:  # Debian's python3-pandas is optional
    _pandas = None


class Results(list):
    """The episodes of a run, one dict per episode (results.json's keys: task, policy, seed,
    status, success, completion_time, ... labels), with the run's provenance in .info."""

    info = None


def load_results(path, dataframe=None):
    """DIR/results.json (or the file itself) as rows: a pandas DataFrame when pandas is
    importable (dataframe=None) or asked for (True), else a Results list of dicts whose .info
    is the provenance (versions, options, metric constants)."""
    run = json.loads(_hribench.load_results_json(str(path)))
    if dataframe is None:
        dataframe = _pandas is not None
    if dataframe:
        if _pandas is None:
            raise ImportError("load_results(dataframe=True) needs pandas (python3-pandas)")
        frame = _pandas.DataFrame(run["episodes"])
        frame.attrs["info"] = {k: v for k, v in run.items() if k != "episodes"}
        return frame
    rows = Results(run["episodes"])
    rows.info = {k: v for k, v in run.items() if k != "episodes"}
    return rows
