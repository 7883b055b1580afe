"""Type stubs of the extension module ``hsid._hsid`` (re-exported by ``hsid``)."""

from typing import Any, Iterable, List, Literal, Optional, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

FloatArray = npt.ArrayLike
"""Samples: a 1-D float array, or anything ``numpy.asarray`` makes one of (a list, a pandas
Series, a memoryview); integers, booleans, complex numbers, objects and text are refused."""

__version__: str
"""The package's version (the workspace's)."""
Direction = Literal["ascending", "descending"]

class HsidError(Exception):
    """Base of every error of hsid; ``kind`` names the library's error variant."""

    kind: str

class DataError(HsidError):
    """Bad data: arrays (dtype, shape, NaN, lengths, inputs outside the interval), model
    files or checkpoints."""

class SettingsError(HsidError):
    """Bad settings: interval, segments, knots, horizons, order, hold, units, plant spec."""

class IdentificationError(HsidError):
    """The identification failed on valid data and settings (no dynamics, rank deficiency,
    an unstable model, a refinement that failed at every order)."""

class Model:
    """An identified Hammerstein model: an input element with an ascending and a descending
    border (piecewise linear on their knots), then ``x(t+1) = A x(t) + B h(t)``,
    ``y(t) = C x(t) + D h(t)``. It is the model file (format hsid-model/1) that
    ``hsid identify --json`` writes."""

    def __init__(self, text: str, notes: Optional[List[str]] = None) -> None:
        """The model of a model file's JSON text, as ``Model.from_json(text)``; ``notes`` are
        what its identification said (pickling keeps them)."""
    def __reduce__(self) -> Tuple[type, Tuple[str, List[str]]]:
        """Pickling, ``copy.copy`` and ``copy.deepcopy`` through the JSON text and the notes."""
    def __eq__(self, other: object) -> bool:
        """Equal when the model files are (every number, setting, sample time and unit; not
        the notes): ``Model.from_json(m.to_json()) == m``."""
    def __hash__(self) -> int:
        """The hash of the model file's contents, consistent with ``==``."""
    @staticmethod
    def from_json(text: str) -> Model:
        """Reads a model file (format hsid-model/1) from its JSON text."""
    def to_json(self) -> str:
        """The model file as JSON text, byte for byte what ``hsid identify --json`` writes."""
    @property
    def notes(self) -> list[str]:
        """What the identification chose and did, one line each, as ``hsid identify`` prints
        them (empty for a model read from JSON)."""
    @property
    def order(self) -> int:
        """Model order n."""
    @property
    def poles(self) -> npt.NDArray[np.complex128]:
        """Poles of the linear part (eigenvalues of A)."""
    @property
    def A(self) -> npt.NDArray[np.float64]:
        """State matrix, order x order."""
    @property
    def B(self) -> npt.NDArray[np.float64]:
        """Input vector, 1-D (``to_dlti()`` and ``to_control()`` give it as an n x 1 column)."""
    @property
    def C(self) -> npt.NDArray[np.float64]:
        """Output vector, 1-D (``to_dlti()`` and ``to_control()`` give it as a 1 x n row)."""
    @property
    def D(self) -> float:
        """Feedthrough."""
    @property
    def mu0(self) -> float:
        """H(u_min), the element's output at the lower end of the interval."""
    @property
    def u_min(self) -> float:
        """Lower end of the input interval."""
    @property
    def u_max(self) -> float:
        """Upper end of the input interval."""
    @property
    def knots_asc(self) -> npt.NDArray[np.float64]:
        """Knots of the ascending border."""
    @property
    def knots_desc(self) -> npt.NDArray[np.float64]:
        """Knots of the descending border."""
    @property
    def nonlinearity(self) -> Optional[Literal["backlash", "switch", "static"]]:
        """The input element, None when not recorded (a solved checkpoint's two paths)."""
    @property
    def std(self) -> Optional[dict[str, Any]]:
        """Standard deviations of a refined model: ``poles`` ([re, im] each), ``mu0``,
        ``border_asc``, ``border_desc`` and ``gap`` (of ``mean_gap``: the model file's, from
        the refinement's whole covariance of the borders; in a file without it, propagated to
        first order from the border values' standard deviations, the two borders' first values
        one parameter μ0 and the others taken as uncorrelated; None where the mean gap is not
        defined); None for a model that was not refined."""
    @property
    def mean_gap(self) -> Optional[float]:
        """The mean gap of the borders (input units) as ``hsid identify`` reports it: the mean
        of the defined ``gap_at`` after an ascent and after a descent at 5 equally spaced
        interior inputs; None for a static element or where no gap is defined."""
    @property
    def ts(self) -> Optional[float]:
        """Sample time in seconds."""
    @property
    def units(self) -> Optional[dict[str, str]]:
        """``{"input": ..., "output": ...}``."""
    @overload
    def border(self, direction: Direction, u: float) -> float: ...
    @overload
    def border(self, direction: Direction, u: FloatArray) -> npt.NDArray[np.float64]:
        """The border of ``direction`` at ``u`` (inside [u_min, u_max])."""
    @overload
    def gap_at(self, direction: Direction, u: float) -> float: ...
    @overload
    def gap_at(self, direction: Direction, u: FloatArray) -> npt.NDArray[np.float64]:
        """How far the input must travel back after a reversal at ``u`` on path
        ``direction`` before the element's output moves; NaN where undefined."""
    def simulate(
        self, u: FloatArray, *, strict_interval: bool = False
    ) -> npt.NDArray[np.float64]:
        """The model's output for the input ``u`` from rest; for an integrating model the
        plant's output (the increments summed from 0). Where ``u`` leaves [u_min, u_max] the
        borders continue linearly on their end segments' lines, with a ``UserWarning``
        saying how many samples lie outside; ``strict_interval=True`` raises ``DataError``
        (kind ``input_out_of_range``) instead."""
    @property
    def integrating(self) -> bool:
        """True for the stable part of an integrating plant (one pole at z = 1)."""
    @overload
    def element(self, u: float, *, strict_interval: bool = False) -> float: ...
    @overload
    def element(
        self, u: FloatArray, *, strict_interval: bool = False
    ) -> npt.NDArray[np.float64]:
        """The element's output h(t) for the input ``u``, the signal the linear part
        (``to_dlti()``) is driven by when the model simulates ``u`` from rest; outside
        [u_min, u_max] as ``simulate``."""
    def to_dlti(self) -> Any:
        """The linear part as ``scipy.signal.dlti(A, B, C, D, dt=ts)`` (B n x 1, C 1 x n;
        ``dt=True`` without a sample time); its input is ``element(u)``. Needs scipy."""
    def to_control(self) -> Any:
        """The linear part as a python-control ``StateSpace`` with ``dt=ts`` (True without a
        sample time). Needs the ``control`` package."""

def excite(
    umin: float, umax: float, samples: int, *, hold: int = 300, seed: int = 1
) -> npt.NDArray[np.float64]:
    """The method's excitation (Table I of the paper), equal to ``hsid excite``; ``samples``
    must exceed ``hold`` (``SettingsError`` of kind ``excitation_too_short`` otherwise, as
    ``hsid excite`` refuses it)."""

def simulate_plant(
    spec: Union[dict[str, Any], str], u: FloatArray, *, seed: Optional[int] = None
) -> npt.NDArray[np.float64]:
    """The output of the true plant ``spec`` (the ``hsid simulate --plant`` format) for ``u``."""

def identify(
    u: FloatArray,
    y: FloatArray,
    umin: float,
    umax: float,
    *,
    segments: Union[int, Literal["auto"], None] = None,
    knots: Union[FloatArray, Tuple[FloatArray, FloatArray], None] = None,
    nonlinearity: Optional[Literal["backlash", "switch", "static"]] = None,
    f: Optional[int] = None,
    p: Optional[int] = None,
    order: Optional[int] = None,
    hold: int = 300,
    ts: Optional[float] = None,
    units: Optional[dict[str, str]] = None,
    refine: bool = True,
    integrating: Optional[bool] = None,
    detrend: bool = False,
    mu0: Optional[float] = None,
    fit: Literal["auto", "none", "simulation"] = "auto",
    reference: Optional[FloatArray] = None,
    basis: Literal["hat", "ramp"] = "hat",
    settle: Optional[int] = None,
) -> Model:
    """A model from ``(u, y)`` as ``hsid identify`` makes it (the library's one identify
    workflow): segments, horizons and order from the data and refined by default (segments
    with fewer than 10 samples of their path merged into a neighbour unless knots are given), the element
    itself fitted by simulation error when the input reverses inside the range (``fit``), the
    closed-loop estimate with ``reference``; the linear model (one segment, output error)
    reported instead when it simulates the held-out last quarter of the record better or when
    the element's model cannot be identified; a record whose output keeps a unit root
    identified as integrating unless ``integrating`` is given. ``refine=False, segments=7,
    f=10, p=10`` is the paper's estimator. ``Model.notes`` says what was chosen and done."""

def regressor(
    u: FloatArray,
    y: FloatArray,
    umin: float,
    umax: float,
    *,
    segments: Optional[int] = None,
    knots: Union[FloatArray, Tuple[FloatArray, FloatArray], None] = None,
    nonlinearity: Literal["backlash", "switch", "static"] = "backlash",
    hold: int = 300,
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The data the subspace identification works on, ``(z, ybar)``: the hat-basis regressor
    channels ``z`` (shape ``(len(u) - hold, channels)``: the ascending path's segments, then
    the descending path's; one set shared by both directions for ``"static"``) and
    ``ybar = y - mu0`` after the hold (mu0 the mean of the hold's settled second half), the
    values ``identify`` accumulates with the same settings. ``segments`` defaults to 7; with
    ``hold=0`` ``ybar`` is ``y - y[0]``."""

def solve_checkpoint(state: bytes, solver: str = "dense") -> Model:
    """The model of an identifier's checkpoint, as ``hsid solve --state [--solver]`` solves it:
    ``solver`` is ``"dense"`` or ``"structured"`` (the firmware's solve; ``SettingsError`` for
    settings it does not take, e.g. μ0 estimated)."""

def solve_many(
    states: Iterable[Union[bytes, bytearray, memoryview]], threads: Optional[int] = None
) -> List[Union[Model, HsidError]]:
    """Many checkpoints solved across ``threads`` worker threads (default: one per core), the GIL
    released: in order, a ``Model`` per checkpoint that solved and the ``HsidError`` (returned,
    not raised; ``.kind`` names it) per checkpoint that did not. One bytes object instead of a
    list raises ``DataError`` of kind ``not_a_list``, an item that is not bytes ``not_bytes``."""

def diagnose(
    u: FloatArray,
    y: FloatArray,
    umin: Optional[float] = None,
    umax: Optional[float] = None,
    *,
    u_val: Optional[FloatArray] = None,
    y_val: Optional[FloatArray] = None,
    split: float = 0.7,
    validation_skip: Optional[int] = None,
    nonlinearity: Literal["backlash", "switch", "static"] = "backlash",
    segments: int = 7,
    knots: Union[FloatArray, Tuple[FloatArray, FloatArray], None] = None,
    order: Optional[int] = None,
    hold: int = 300,
    f: Optional[int] = None,
    p: Optional[int] = None,
    ts: Optional[float] = None,
    units: Optional[dict[str, str]] = None,
) -> dict[str, Any]:
    """The diagnosis of ``(u, y)`` as the JSON report of ``hsid diagnose --json``: the model,
    the checks of the data against the method's assumptions, the residual tests and the
    effects added; validated on ``(u_val, y_val)`` or on the last ``1 - split`` of the record.
    ``ts`` and ``units``, checked as ``identify`` checks them, are added as ``"ts"`` and
    ``"units"``."""

def read_csv_columns(
    path: Any,
    *,
    u: str = "u",
    y: Optional[str] = "y",
    time: Optional[str] = None,
    delimiter: Optional[str] = None,
) -> dict[str, Any]:
    """The columns ``u``, ``y`` and the time column of an hsid CSV record with its sample
    time and units, as a dict ``{"u", "y", "t", "ts", "units"}``; ``hsid.read_csv`` wraps it."""
