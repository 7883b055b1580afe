"""Records from files and tables: ``read_csv`` (hsid's own CSV files, read by the host
library's reader as the command line reads them) and the pandas DataFrame entry of
``identify`` and ``diagnose``."""

from __future__ import annotations

import dataclasses
import sys
from typing import Any, Optional

import numpy as np

from . import _hsid

#: Relative tolerance of a time column's steps around their mean step: 0.1 %, the command
#: line's (``hsid_host::units::TS_TOLERANCE``).
TS_TOLERANCE = 1e-3


@dataclasses.dataclass(frozen=True, eq=False)
class CsvRecord:
    """A record read by :func:`read_csv`: the input ``u``, the output ``y`` (None for a file
    without it, e.g. what ``hsid excite`` writes), the sample time ``ts`` in seconds (from the
    ``# ts = … s`` comment and the time column, None when neither states it), the ``units``
    ``{"input": …, "output": …}`` of the ``# input unit`` / ``# output unit`` comments (or
    None) and the time column ``t`` (or None)."""

    u: np.ndarray
    y: Optional[np.ndarray]
    ts: Optional[float]
    units: Optional[dict]
    t: Optional[np.ndarray]

    def identify(self, umin: float, umax: float, **kwargs: Any) -> _hsid.Model:
        """``hsid.identify(self.u, self.y, umin, umax, ts=self.ts, units=self.units,
        **kwargs)``: the model of the record, its sample time and units recorded (a ``ts`` or
        ``units`` given here replaces the file's)."""
        if self.y is None:
            raise _error(
                _hsid.DataError,
                "missing_column",
                "the record has no output column y: read_csv(path, y=NAME) names it",
            )
        kwargs.setdefault("ts", self.ts)
        kwargs.setdefault("units", self.units)
        return _hsid.identify(self.u, self.y, umin, umax, **kwargs)


def read_csv(
    path: Any,
    *,
    u: str = "u",
    y: Optional[str] = "y",
    time: Optional[str] = None,
    delimiter: Optional[str] = None,
) -> CsvRecord:
    """Reads a record of hsid's CSV format (what ``hsid excite`` and ``hsid simulate`` write,
    what ``hsid identify --data`` reads) with the host library's reader, as the command line
    reads it: the columns ``u`` and ``y`` (the default ``y`` only when the file has it;
    ``y=None`` reads the input alone), the header comments ``# ts = 0.01 s``,
    ``# input unit = V`` and ``# output unit = deg``, and the time column ``time`` (default
    ``t`` when the file has it), whose step must be uniform within 0.1 % and agree with the
    ``# ts`` comment. ``delimiter`` is ``","``, ``";"``, ``"\\t"`` or None (sniffed from the
    header). Bad files raise ``DataError`` naming the file and line (kinds ``csv_file``,
    ``missing_column``, ``csv``, ``time_not_uniform``, ``time_not_increasing``,
    ``sample_time``, ``units``)."""
    d = _hsid.read_csv_columns(path, u=u, y=y, time=time, delimiter=delimiter)
    return CsvRecord(u=d["u"], y=d["y"], ts=d["ts"], units=d["units"], t=d["t"])


def _error(cls: type, kind: str, message: str) -> Exception:
    e = cls(message)
    e.kind = kind
    return e


def is_frame(obj: Any) -> bool:
    """Whether ``obj`` is a pandas DataFrame (pandas is never imported here: a program that
    holds a DataFrame has imported it)."""
    pd = sys.modules.get("pandas")
    return pd is not None and isinstance(obj, pd.DataFrame)


def _seconds(values: Any, name: str) -> np.ndarray:
    """Times in seconds: datetimes and timedeltas as seconds from the first, numbers as they
    are (seconds)."""
    a = np.asarray(values)
    if a.dtype.kind == "M":
        a = (a - a[0]) / np.timedelta64(1, "s") if len(a) else a.astype(float)
    elif a.dtype.kind == "m":
        a = a / np.timedelta64(1, "s")
    elif a.dtype.kind not in "fiu":
        raise _error(
            _hsid.DataError,
            "time_column",
            f"{name} has dtype {a.dtype}: give times in seconds, datetimes or timedeltas",
        )
    return a.astype(float)


def sample_time_of(t: np.ndarray, name: str) -> float:
    """The sample time of the times ``t`` (seconds): the mean step, every step within
    :data:`TS_TOLERANCE` of it, as the command line takes it from a time column."""
    if len(t) < 2:
        raise _error(
            _hsid.DataError, "time_column", f"{name} has fewer than two rows: no sample time"
        )
    if not np.all(np.isfinite(t)):
        i = int(np.flatnonzero(~np.isfinite(t))[0])
        raise _error(_hsid.DataError, "time_column", f"{name}[{i}] is {t[i]}: give finite times")
    step = np.diff(t)
    if np.any(step <= 0):
        i = int(np.flatnonzero(step <= 0)[0]) + 1
        raise _error(
            _hsid.DataError,
            "time_not_increasing",
            f"{name}[{i}] = {t[i]} does not increase (the row before has {t[i - 1]}): "
            "sort the frame or drop the time",
        )
    ts = (t[-1] - t[0]) / (len(t) - 1)
    bad = np.flatnonzero(np.abs(step - ts) > TS_TOLERANCE * ts)
    if len(bad):
        i = int(bad[0]) + 1
        raise _error(
            _hsid.DataError,
            "time_not_uniform",
            f"{name}[{i}]: time step {step[i - 1]:.6g} differs from the mean step {ts:.6g} by "
            f"more than {TS_TOLERANCE * 100:g} %; the method needs uniform sampling (resample "
            "the frame, or identify its uniform parts)",
        )
    return float(ts)


def frame_columns(
    frame: Any, u: str, y: str, time: Optional[str], ts: Optional[float]
) -> tuple[np.ndarray, np.ndarray, Optional[float]]:
    """The input and output columns of ``frame`` and the sample time: of the column ``time``
    when named, else of a column ``t`` (the command line's default time column), else of a
    datetime or timedelta index, else ``ts``; a ``ts`` given besides must agree within
    :data:`TS_TOLERANCE`."""
    for role, col in (("u", u), ("y", y)) + ((("time", time),) if time is not None else ()):
        if col not in frame.columns:
            raise _error(
                _hsid.DataError,
                "missing_column",
                f"{role}={col!r} is not a column of the frame (its columns: "
                f"{', '.join(map(repr, frame.columns))}): name the column with {role}=",
            )
    source = None
    if time is not None:
        source = (frame[time].to_numpy(), f"column {time!r}")
    elif "t" in frame.columns and "t" not in (u, y):
        source = (frame["t"].to_numpy(), "column 't'")
    elif np.asarray(frame.index).dtype.kind in "mM":
        source = (np.asarray(frame.index), "the frame's index")
    if source is not None:
        stated = sample_time_of(_seconds(*source), source[1])
        if ts is not None and abs(ts - stated) > TS_TOLERANCE * stated:
            raise _error(
                _hsid.SettingsError,
                "sample_time",
                f"ts={ts} but {source[1]} gives a sample time of {stated:.6g} s: drop one or "
                "make them agree",
            )
        ts = stated if ts is None else ts
    return frame[u].to_numpy(), frame[y].to_numpy(), ts


def identify(*args: Any, **kwargs: Any) -> _hsid.Model:
    """``identify(u, y, umin, umax, **settings)``, or ``identify(frame, umin, umax, *,
    u="u", y="y", time=None, **settings)`` with a pandas DataFrame: the columns named ``u``
    and ``y`` (and ``reference`` when it is a column name), the sample time from the column
    ``time`` (default: a column ``t``, else a datetime or timedelta index; uniform within
    0.1 %), else ``ts``. Everything else as ``hsid._hsid.identify``."""
    if args and is_frame(args[0]):
        return from_frame(*args, **kwargs)
    return _hsid.identify(*args, **kwargs)


def from_frame(
    frame: Any,
    umin: float,
    umax: float,
    *,
    u: str = "u",
    y: str = "y",
    time: Optional[str] = None,
    ts: Optional[float] = None,
    **kwargs: Any,
) -> _hsid.Model:
    """The model of the pandas DataFrame ``frame``: ``identify`` on its columns ``u`` and
    ``y``, the sample time of its time column or index (see ``identify``) unless ``ts``
    alone states it; ``reference`` may name a column."""
    uu, yy, ts = frame_columns(frame, u, y, time, ts)
    ref = kwargs.get("reference")
    if isinstance(ref, str):
        if ref not in frame.columns:
            raise _error(
                _hsid.DataError,
                "missing_column",
                f"reference={ref!r} is not a column of the frame",
            )
        kwargs["reference"] = frame[ref].to_numpy()
    return _hsid.identify(uu, yy, umin, umax, ts=ts, **kwargs)


def diagnose(*args: Any, **kwargs: Any) -> dict:
    """``diagnose(u, y, ...)``, or ``diagnose(frame, umin=None, umax=None, *, u="u",
    y="y", time=None, ...)`` with a pandas DataFrame (columns and sample time as
    ``identify`` takes them). Everything else as ``hsid._hsid.diagnose``."""
    if args and is_frame(args[0]):
        frame, rest = args[0], args[1:]
        u = kwargs.pop("u", "u")
        y = kwargs.pop("y", "y")
        time = kwargs.pop("time", None)
        uu, yy, ts = frame_columns(frame, u, y, time, kwargs.pop("ts", None))
        return _hsid.diagnose(uu, yy, *rest, ts=ts, **kwargs)
    return _hsid.diagnose(*args, **kwargs)
