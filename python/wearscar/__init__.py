"""wearscar for Python: the sliding friction coefficient of reciprocating
friction tests from the force record and a profilometer scan of the worn
track (wear-scar interaction, Q = P (k + s mu) / (1 - s mu k)).

    import wearscar
    test = wearscar.simulate("B-RT-R", cycles=60, seed=3)
    result = wearscar.fuse(test.force, test.scan, running_in=20)
    result.mu_to_quote, result.status, result.summary["headline"]

Keyword arguments are the command line's options with '_' for '-' and the
same defaults (``wearscar fuse --help`` lists them), for example
``spring=25``, ``k_estimate="cycle"``, ``running_in=20``, ``slope="scan"``,
``no_lugre=True``, ``columns="x=Pos:um,q=Ff,p=Fn"``; a list gives a
repeatable option each of its values, and is refused for the others. Bad values raise
``OptionError`` (a ValueError) naming the keyword; a keyword that is not
an option raises TypeError (with the closest one it may have meant); bad
files raise ``ForceError`` or
``ScanError`` naming the file, the line or byte, what was found and what
was expected; a folder that cannot be written raises ``OutputError`` (an
OSError). Long calls release the GIL.
"""

import errno as _errno
import json as _json
import math as _math
import os as _os
import tempfile as _tempfile
import time as _time
import warnings as _warnings

from ._wearscar import (ForceError, ForceRecord, FusionError, HeightMap,
                        OptionError, OutputError, ScanError, git_commit,
                        version)
from . import _wearscar

__all__ = [
    "read_force", "read_scan", "fuse", "audit", "simulate", "watch", "Result",
    "AuditRows",
    "Simulation", "ForceRecord", "HeightMap", "ForceError", "ScanError",
    "FusionError", "OptionError", "OutputError", "version", "git_commit", "__version__",
]

__version__ = version()


def _record_to_dict(record):
    """The record as plain Python values: lists in mm, N, s, and the
    metadata."""
    return {"time_s": record.time_s.tolist(), "x_mm": record.x_mm.tolist(),
            "q_n": record.q_n.tolist(), "p_n": record.p_n.tolist(),
            "metadata": record.metadata}


def _map_to_dict(height_map):
    """The map as plain Python values (NaN where not measured)."""
    return {"height_mm": height_map.height_mm.tolist(),
            "dx_mm": height_map.dx_mm, "dy_mm": height_map.dy_mm,
            "metadata": height_map.metadata}


ForceRecord.to_dict = _record_to_dict
HeightMap.to_dict = _map_to_dict


def _existing_or_coming(path):
    """A path as text: the file may not exist yet (watch waits for it)."""
    if not isinstance(path, (str, bytes, _os.PathLike)):
        raise TypeError("watch(path=...): expected a path; found {}".format(
            type(path).__name__))
    return _os.fspath(path)


def _args(options):
    """Keyword arguments as the library's settings, (name, text) pairs:
    spring=10.19 -> ("spring", "10.19"); True and False -> "true" and
    "false"; None -> left out; a list or tuple -> the setting repeated over
    its items."""
    out = []
    for key, value in options.items():
        name = key.replace("_", "-")
        if value is None:
            continue
        for item in value if isinstance(value, (list, tuple)) else [value]:
            out.append((name, _text(item)))
    return out


def _text(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, _os.PathLike):
        return _os.fspath(value)
    return str(value)


def _existing(path):
    """The path as text; FileNotFoundError when nothing is there."""
    path = _os.fspath(path)
    if not _os.path.exists(path):
        raise FileNotFoundError(_errno.ENOENT, _os.strerror(_errno.ENOENT),
                                path)
    return path


def _path_or(value):
    """A path (checked) as text, or the object itself (a record, a map)."""
    return _existing(value) if isinstance(value, (str, _os.PathLike)) else value


def read_force(path, **options):
    """The force export at `path` as a ForceRecord (NumPy arrays time_s,
    x_mm, q_n, p_n and a metadata dict). Options: time_column, x_column,
    q_column, p_column, columns, x_unit, force_unit, time_unit, rate,
    lenient."""
    return _wearscar._read_force(_existing(path), _args(options))


def read_scan(path, **options):
    """The height map at `path` (any format `wearscar scan` reads) as a
    HeightMap (height_mm: NumPy float32 rows x cols in mm, NaN where not
    measured; dx_mm, dy_mm; metadata). Options: measurement, large_maps,
    max_pixel_aspect, ascii_pitch, ascii_unit."""
    return _wearscar._read_scan(_existing(path), _args(options))



# Columns that count or number things: integers (int64) when every value
# is a whole number, as the CSV writes them.
_INTEGER_COLUMNS = {"cycle", "running_in", "direction", "index", "specimen",
                    "samples", "bin", "effective_cycles", "slip_fallback"}


def _typed(column, values):
    if column in _INTEGER_COLUMNS or column.endswith("_count"):
        import numpy as np
        if values.size and np.all(np.isfinite(values)) and \
                np.all(values == np.round(values)):
            return values.astype(np.int64)
    return values

class Result:
    """One analysed test: what `wearscar fuse --no-figures` writes.

    summary: result.json as a dict (mu-hat statistics, both slopes, the
      verdict, wear, provenance, every option).
    tables: {"cycles": {"cycle": array, "mu_hat_force": array, ...},
      "loops": ..., "detail": ..., "cost_curve": ..., "profiles": ...}.
    mu_to_quote: the value to quote (the headline's mu), None where the
      status gives none, and no_mu_to_quote_because then says why; status:
      "explained", "not settled", "not explained", "not judged" or "not
      fitted". mu_hat: mean mu-hat with k from P over the compared cycles (a
      comparison where the scan's k is quoted); mu_hat_per_cycle: each
      cycle's (from cycle 1, running-in included); frame("cycles"): a table
      as a pandas DataFrame.
    """

    def __init__(self, output):
        self._output = output
        self.name = output.name
        self.summary = _json.loads(output.summary_json())
        self.tables = {}
        for file, columns, values in output.tables():
            key = file[:-4] if file.endswith(".csv") else file
            self.tables[key] = {c: _typed(c, values[:, i])
                                for i, c in enumerate(columns)}

    @property
    def cycles(self):
        """cycles.csv: one entry per cycle, numbered from 1."""
        return self.tables["cycles"]

    @property
    def mu_hat(self):
        return self.summary["comparison"]["mu_hat_force"]["mean"]

    @property
    def mu_to_quote(self):
        """The coefficient to quote, None where there is none (see
        no_mu_to_quote_because)."""
        return self.summary["quote"]["mu"]

    @property
    def status(self):
        return self.summary["quote"]["status"]

    @property
    def no_mu_to_quote_because(self):
        """Why there is no mu to quote ("" where there is one)."""
        return self.summary["quote"]["reason"]

    @property
    def mu_hat_per_cycle(self):
        """mu-hat (k from P) of each cycle, from cycle 1 (NumPy array)."""
        return self.cycles["mu_hat_force"]

    def frame(self, table="cycles"):
        """A table ("cycles", "loops", "detail", ...) as a pandas DataFrame
        (pandas is optional: the tables are dicts of NumPy arrays)."""
        if table not in self.tables:
            raise KeyError("wearscar: no table {!r} in this result; it has {}"
                           .format(table, ", ".join(sorted(self.tables))))
        try:
            import pandas
        except ImportError as e:
            raise ImportError(
                "wearscar: Result.frame needs pandas (apt-get install "
                "python3-pandas); result.tables[{!r}] is a dict of NumPy "
                "arrays without it".format(table)) from e
        return pandas.DataFrame(self.tables[table])

    @property
    def mu_hat_scan(self):
        stat = self.summary["comparison"].get("mu_hat_scan")
        return None if stat is None else stat["mean"]

    @property
    def explained(self):
        return self.summary["verdict"]["explained"]

    def to_dict(self):
        """The summary and the tables (lists) as plain Python values."""
        return {"summary": self.summary,
                "tables": {name: {c: v.tolist() for c, v in t.items()}
                           for name, t in self.tables.items()}}

    def write(self, out, figures=False):
        """Writes the files of `wearscar fuse --no-figures` into `out` and,
        with figures=True (or "svg", "png", "svg,png"), the figures of
        `wearscar fuse` too, drawn by gnuplot (True: SVG, the command's
        default); returns their paths. Figures that could not be drawn are
        a warning (also in result.json), not an error."""
        written, why = self._output.write(_os.fspath(out),
                                          _figure_formats(figures))
        if why:
            _warnings.warn("wearscar: " + why, RuntimeWarning, stacklevel=2)
        return written

    def __repr__(self):
        quoted = self.mu_to_quote
        return "<wearscar.Result {}: {}, {}>".format(
            self.name,
            self.status if quoted is None else "mu {:.4f}".format(quoted),
            self.summary["verdict"]["summary"][:60])


def _figure_formats(figures):
    """"" for none, else the --figure-format text."""
    if figures is True:
        return "svg"
    if not figures:
        return ""
    return str(figures)


def fuse(force, scan=None, name=None, detail_cycle=None, loops=None,
         **options):
    """Analyses one test. `force` is a path or a ForceRecord, `scan` a path,
    a HeightMap or None (the force slope only). Options are those of
    `wearscar fuse` (reading, method, verdict, scan); cycles are numbered
    from 1 (detail_cycle, loops). Returns a Result."""
    return Result(_wearscar._fuse(_path_or(force), _path_or(scan),
                                  _args(options), name or "",
                                  detail_cycle or 0, list(loops or [])))


class AuditRows(list):
    """What audit() returns: one dict per specimen (its result.json with
    species, plane, direction, factors, or "error"), and the batch as
    tables: frame("summary") (summary.csv's columns), frame("groups") (per
    factor level and group: specimens, mean, spread, 95% interval),
    frame("differences") (between levels, with p); `groups` as
    groups.json holds it (with the planning line and those left out)."""

    KINDS = ("summary", "groups", "differences")

    def __init__(self, rows, summary_csv, groups):
        super().__init__(rows)
        self.summary_csv = summary_csv
        self.groups = groups

    def frame(self, kind="summary"):
        """A batch table ("summary", "groups" or "differences") as a pandas
        DataFrame."""
        if kind not in self.KINDS:
            raise KeyError("wearscar: no table {!r} in an audit; it has {}"
                           .format(kind, ", ".join(self.KINDS)))
        try:
            import pandas
        except ImportError as e:
            raise ImportError(
                "wearscar: AuditRows.frame needs pandas (apt-get install "
                "python3-pandas)") from e
        if kind == "summary":
            import io
            return pandas.read_csv(io.StringIO(self.summary_csv))
        records = []
        for g in self.groups:
            for item in g["levels" if kind == "groups" else "differences"]:
                one = {"quantity": g["quantity"]}
                for key, value in item.items():
                    if key == "interval95":
                        one["low95"], one["high95"] = value
                    else:
                        one[key] = value
                records.append(one)
        return pandas.DataFrame(records)


def audit(folder, out=None, jobs=0, name_pattern=None, recursive=True,
          figures=False, factors=None, **options):
    """Pairs and analyses every specimen of a folder (or a manifest.csv)
    as `wearscar audit` does, `jobs` at a time (0 = one per core), and
    compares its groups (`factors`, a list: those to compare by; default
    every factor with two levels). Returns an AuditRows: one dict per
    specimen (its result.json with species, plane, direction, factors, or
    "error") and frame("summary"), frame("groups"), frame("differences").
    With `out`, writes there what `wearscar audit --no-figures` writes (a
    folder per specimen, summary.csv, .jsonl and .json, groups.csv,
    report.html; the earlier specimens of an audit there are kept, as the
    command keeps them); with figures=True (or "svg", "png", "svg,png")
    the figures too, as `wearscar audit --figure-format` draws them."""
    answer = _json.loads(_wearscar._audit(
        _existing(folder), _args(options), name_pattern or "", recursive,
        jobs, _os.fspath(out) if out is not None else "",
        _figure_formats(figures), list(factors or [])))
    if out is None:
        return AuditRows(answer["rows"], answer["summary_csv"],
                         answer["groups"])
    with open(_os.path.join(_os.fspath(out), "summary.csv")) as f:
        summary_csv = f.read()
    with open(_os.path.join(_os.fspath(out), "groups.json")) as f:
        groups = _json.load(f)
    return AuditRows(answer["rows"], summary_csv, groups)


def watch(path, poll=0.1, idle=60.0, until_cycles=None, steady_cycles=30,
          steady_band=0.005, steady_hold=5, max_depth=None, pattern=None,
          **options):
    """Follows a force file the tribometer's software is still writing, as
    `wearscar watch` does, and yields one dict per cycle as it completes:
    cycle (from 1), end_time_s, mu_hat with k from P over it and the cycles
    before it (or from a depth channel, as `fuse` decides: a "profile"
    event says so; mu_hat_low, mu_hat_high: its 95% interval), mu_mean,
    mu_energy, J, J_floor, J_excess, depth_mm (the track's depth from the
    spring, or the depth channel's), running_in, and "events": the alerts
    raised with it (dicts of kind: running-in, steady, verdict, depth,
    restart, profile or block; cycle; message; good: true for mu-hat steady
    and a verdict that the loops are explained). "Steady" is said once its
    rule (steady_cycles, steady_band) has held on steady_hold cycles.
    Ends when the file has not grown for `idle` seconds (a last dict with
    cycle None carries the "idle" event and any other not yet given) or
    after `until_cycles` cycles; a caller may stop at any time (break).
    With `pattern` ("run_*.csv"), `path` is a folder where the software
    starts a file per block: the matching files, in their names' natural
    order, are followed as one test (a "block" event says when one is
    finished and the next started), as `wearscar watch DIR --pattern`
    does. Options are those of `wearscar fuse` (spring=..., columns=...)."""
    with _tempfile.TemporaryDirectory(prefix="wearscar-watch-") as work:
        steady = (int(steady_cycles), float(steady_band), int(steady_hold))
        yield from _watch(path, poll, idle, until_cycles, steady, max_depth,
                          pattern, work, options)


def _watch(path, poll, idle, until_cycles, steady, max_depth, pattern, work,
           options):
    joined = _os.path.join(work, "blocks.joined.csv") if pattern else ""
    w = _wearscar._Watcher(_existing_or_coming(path), _args(options), *steady,
                           _math.nan if max_depth is None else float(max_depth),
                           pattern or "", joined)
    taken, grew, count, pending = -1, _time.monotonic(), 0, []
    while True:
        cycles, events, offset = w.poll(_time.monotonic() - grew > 1.0)
        pending += events
        if offset != taken:
            taken, grew = offset, _time.monotonic()
        elif _time.monotonic() - grew > idle:
            pending.append({
                "kind": "idle", "cycle": count,
                "message": "{} has not grown for {:g} s: the writer stopped"
                           .format(_os.fspath(path), idle),
                "good": False})
        for c in cycles:
            c["events"], pending = pending, []
            count = c["cycle"]
            yield c
            if until_cycles is not None and count >= until_cycles:
                return
        if any(e["kind"] == "idle" for e in pending):
            yield {"cycle": None, "events": pending}
            return
        _time.sleep(poll)


class Simulation:
    """A simulated test: force (ForceRecord), scan (HeightMap) and truth
    (the ground truth: mu per cycle, noise, effects, geometry)."""

    def __init__(self, simulated):
        self.force = simulated.force
        self.scan = simulated.scan
        self.truth = _json.loads(simulated.truth_json)
        self.case = self.truth["case"]

    def to_dict(self):
        """The force record, the scan and the truth as plain dicts."""
        return {"force": self.force.to_dict(), "scan": self.scan.to_dict(),
                "truth": self.truth}

    def __repr__(self):
        return "<wearscar.Simulation {}: {} samples, {} x {} scan>".format(
            self.case, len(self.force), *self.scan.shape)


def simulate(case="B-RT-R", **options):
    """The virtual tribometer and profilometer (`wearscar simulate`): the
    paper's case `case` (a name or a list of names; all=True for the 12)
    with options cycles, rate, amplitude, frequency, scan_cols, scan_rows,
    scan_pitch, noise, elastic, no_elastic, triangle, seed, effect
    ("ploughing=1.0" or a list). Returns a Simulation, or a list of them
    for several cases."""
    if options.get("all"):
        cases = []
    elif isinstance(case, (list, tuple)):
        cases = list(case)
    else:
        cases = [case]
    runs = [Simulation(s) for s in
            _wearscar._simulate(_args({"case": cases, **options}))]
    return runs[0] if len(runs) == 1 and len(cases) == 1 else runs
