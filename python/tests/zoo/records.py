"""Records nobody designed for the method: a record generator written apart from the project's
own Table I generators and simulators (numpy, and scipy.signal for filters only).

Every record is deterministic given its spec (the spec carries its seed). It holds an
estimation part and a separate validation part: the same plant, element and noise level, but
its own input realisation and its own noise realisation. The noise-free output of both parts is
kept, so the noise floor of a model scored on the validation part is known.

Choices, all of them:

Inputs (nominal interval [-1, 1]; the identification is given ``min(u)`` and ``max(u)`` of the
estimation part, as a new user would):

* ``multisine``: random-phase multisine on the record's own frequency grid ``k / N`` (so it is
  periodic over the record and its spectrum is exactly zero outside its band), equal
  amplitudes, band ``[f_lo, f_hi]`` with ``f_lo`` in 10-20 % and ``f_hi`` in 30-60 % of
  Nyquist; scaled to a peak of 1.
* ``noise``: white Gaussian noise through a 4th-order Butterworth low-pass with its corner at
  5-30 % of Nyquist (``scipy.signal.butter``, ``lfilter``), scaled to a peak of 1.
* ``prbs``: a random binary signal of levels -1 and +1 whose clock holds each value for 5-20
  samples (one hold per record), a fair coin at each clock tick.
* ``staircase``: levels uniform in [-1, 1], each held 50-300 samples (a step is a staircase of
  few levels).
* ``chirp``: a linear chirp, amplitude 1, from 0.1 % to 20 % of the sampling rate (0.2 % to 40 %
  of Nyquist) over the record (``scipy.signal.chirp``), with a random start phase.
* ``quantised``: the filtered noise above rounded to 8 equally spaced levels in [-1, 1].
* ``closedloop``: a controller around the element and plant with a staircase reference (levels
  uniform in [-0.6, 0.6], each held 100-400 samples). Proportional-integral
  ``u(t) = u(t-1) + kp (e(t) - e(t-1)) + ki e(t)`` with ``e = r - y`` (the measured, noisy
  output), or proportional only ``u(t) = kp e(t)`` for an integrating plant. The gains start at
  ``kp = 0.5, ki = 0.1`` and are halved until the linear loop, with the element's slope bounded
  by 2.5, has all poles inside 0.995. No saturation, so the controller equation holds at every
  sample. ``u`` is the controller output, the reference is kept in ``r_est`` and ``r_val``.

Plants: ``y = B(q) / F(q) v`` with a delay of one sample (``B(q) = b1 q^-1 + ... + bn q^-n``),
order 1-6. Poles by kind: ``slow`` real poles in [0.9, 0.985] and pairs of radius [0.9, 0.97],
``fast`` real poles in [0.2, 0.7] and pairs of radius [0.4, 0.75], ``resonant`` a lightly
damped pair (radius [0.95, 0.985], angle [0.2, 0.6] rad) with the rest ``mixed`` (real poles in
[0.3, 0.95], pairs of radius [0.5, 0.9]); pair angles in [0.15, 1.2] rad unless stated. An odd
order has one real pole, the others come in pairs. The zeros of ``B`` are real, in [-0.6, 0.7].
The static gain ``B(1) / F(1)`` is normalised to 1. An integrating plant is that plant times
``0.02 / (1 - q^-1)`` (a pole at z = 1, per-sample gain 0.02).

Elements before the plant, ``v = element(u)``:

* ``linear``: ``v = u``.
* ``backlash``: the play operator ``v(t) = min(u(t) + h, max(u(t) - h, v(t-1)))``, total width
  ``2h`` of 4-8 % of the nominal range (``h`` of 2-4 % of 2).
* ``switch``: a relay with a hysteresis band: ``v = u - o`` on the lower border and ``u + o``
  on the upper, ``o`` in [0.1, 0.2]; it jumps to the upper border when ``u`` rises to ``beta``
  and to the lower one when ``u`` falls to ``alpha``, ``alpha = -beta``, ``beta`` in [0.2, 0.4].
* ``deadzone``: ``v = sign(u) max(|u| - d, 0) / (1 - d)``, ``d`` in [0.1, 0.25].
* ``tanh``: ``v = tanh(k u) / tanh(k)``, ``k`` in [1.5, 2.5].

Initial state: a part starts at rest at its first input: the element is first brought from
``u = -1`` (the play's output ``-1 + h``, the relay on its lower border) to ``u(0)``, and the
plant's state is the steady state of ``v`` there. An integrating plant starts with zero state
and output 0. The closed loop starts with ``u(-1) = 0`` and ``e(-1) = 0`` at that state.

Noise: ``y = y_clean + e``, white Gaussian or coloured (white through ``1 / (1 - 0.8 q^-1)``,
tagged ``ar``). Its standard deviation is set from the process's theoretical variance, not the
sample's, so that ``10 log10(var(y_clean) / var(e)) `` on the estimation part is the requested
SNR up to the sampling spread; the validation part uses the same standard deviation. In closed
loop the level is set from a noise-free run of the same loop, and the noise then enters the
loop through the measurement.

Seeds: each spec's seed drives one ``numpy.random.default_rng``, drawn in a fixed order (plant,
element, estimation input, validation input, noise), so records do not depend on one another.
The family (``FAMILY``, 35 records of 2,000-6,000 samples) uses seeds ``1000 + index`` by
default; ``family(base)`` shifts them.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable, List, Optional, Tuple

import numpy as np
from scipy import signal

INPUTS = ("multisine", "noise", "prbs", "staircase", "chirp", "quantised", "closedloop")
ELEMENTS = ("linear", "backlash", "switch", "deadzone", "tanh")
PLANT_KINDS = ("slow", "fast", "resonant", "mixed")
INTEGRATOR_GAIN = 0.02
SLOPE_BOUND = 2.5


@dataclass(frozen=True)
class Spec:
    """What a record is: input kind, plant order and kind, element, noise, length and seed."""

    input: str
    order: int
    element: str
    snr_db: float
    plant: str = "mixed"
    coloured: bool = False
    integrating: bool = False
    samples: int = 4000
    seed: int = 1

    @property
    def name(self) -> str:
        """The record's name, e.g. ``multisine-o3-backlash-20dB`` (``i`` after the order for an
        integrating plant, ``-ar`` for coloured noise)."""
        order = f"o{self.order}{'i' if self.integrating else ''}"
        tail = "-ar" if self.coloured else ""
        return f"{self.input}-{order}-{self.element}-{self.snr_db:g}dB{tail}"


@dataclass
class Plant:
    """The linear part ``B(q) / F(q)`` (delay one, ``num[0] == 0``), integrator included."""

    num: np.ndarray
    den: np.ndarray
    integrating: bool

    @property
    def poles(self) -> np.ndarray:
        """The roots of ``F``."""
        return np.roots(self.den)


@dataclass
class Element:
    """The static or hysteretic element before the plant, with its parameters."""

    kind: str
    h: float = 0.0
    o: float = 0.0
    beta: float = 0.0
    d: float = 0.0
    k: float = 1.0

    def start(self, u0: float) -> "ElementState":
        """The element brought from ``u = -1`` to ``u0``, ready to step."""
        state = ElementState(self, play=-1.0 + self.h, high=False)
        state.step(u0)
        return state


@dataclass
class ElementState:
    """The element's memory: the play's output and the relay's border."""

    element: Element
    play: float
    high: bool

    def step(self, u: float) -> float:
        """The element's output at ``u``, its memory updated."""
        e = self.element
        if e.kind == "linear":
            return u
        if e.kind == "backlash":
            self.play = min(u + e.h, max(u - e.h, self.play))
            return self.play
        if e.kind == "switch":
            if u >= e.beta:
                self.high = True
            elif u <= -e.beta:
                self.high = False
            return u + e.o if self.high else u - e.o
        if e.kind == "deadzone":
            return float(np.sign(u) * max(abs(u) - e.d, 0.0) / (1.0 - e.d))
        if e.kind == "tanh":
            return float(np.tanh(e.k * u) / np.tanh(e.k))
        raise ValueError(f"unknown element {e.kind}")

    def run(self, u: np.ndarray) -> np.ndarray:
        """The element's output for the whole of ``u``."""
        return np.array([self.step(float(x)) for x in u])


@dataclass
class Record:
    """One record: the estimation and validation parts, noisy and noise-free outputs, the
    reference of a closed loop, and the truth that made them."""

    spec: Spec
    plant: Plant
    element: Element
    u_est: np.ndarray
    y_est: np.ndarray
    y_est_clean: np.ndarray
    u_val: np.ndarray
    y_val: np.ndarray
    y_val_clean: np.ndarray
    noise_std: float
    r_est: Optional[np.ndarray] = None
    r_val: Optional[np.ndarray] = None
    gains: Tuple[float, float] = (0.0, 0.0)
    settings: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        """The spec's name."""
        return self.spec.name


# --- plants ---------------------------------------------------------------------------


def _pair(rng: np.random.Generator, radius: Tuple[float, float],
          angle: Tuple[float, float] = (0.15, 1.2)) -> List[complex]:
    r, a = rng.uniform(*radius), rng.uniform(*angle)
    return [r * np.exp(1j * a), r * np.exp(-1j * a)]


def make_plant(rng: np.random.Generator, order: int, kind: str, integrating: bool) -> Plant:
    """A plant of ``order`` poles of ``kind`` (module docstring), static gain 1 (times the
    integrator when ``integrating``)."""
    real = {"slow": (0.9, 0.985), "fast": (0.2, 0.7), "mixed": (0.3, 0.95), "resonant": (0.3, 0.95)}[kind]
    radius = {"slow": (0.9, 0.97), "fast": (0.4, 0.75), "mixed": (0.5, 0.9), "resonant": (0.5, 0.9)}[kind]
    poles: List[complex] = []
    if kind == "resonant" and order >= 2:
        poles += _pair(rng, (0.95, 0.985), (0.2, 0.6))
    while len(poles) + 2 <= order:
        poles += _pair(rng, radius)
    if len(poles) < order:
        poles.append(rng.uniform(*real))
    den = np.real(np.poly(poles))
    zeros = rng.uniform(-0.6, 0.7, size=order - 1)
    b = np.real(np.poly(zeros)) if order > 1 else np.ones(1)
    num = np.concatenate([[0.0], b])
    num = num * np.sum(den) / np.sum(num)
    if integrating:
        num = INTEGRATOR_GAIN * num
        den = np.convolve(den, [1.0, -1.0])
    return Plant(num=num, den=den, integrating=integrating)


def run_plant(plant: Plant, v: np.ndarray) -> np.ndarray:
    """The plant's noise-free output for ``v``: at rest at ``v[0]`` (a stable plant), or from
    zero state (an integrating one)."""
    if plant.integrating:
        return signal.lfilter(plant.num, plant.den, v)
    zi = signal.lfilter_zi(plant.num, plant.den) * v[0]
    return signal.lfilter(plant.num, plant.den, v, zi=zi)[0]


# --- elements -------------------------------------------------------------------------


def make_element(rng: np.random.Generator, kind: str) -> Element:
    """An element of ``kind`` with parameters drawn as the module docstring states."""
    draws = rng.uniform(size=3)
    if kind == "backlash":
        return Element(kind, h=0.04 + 0.04 * draws[0])
    if kind == "switch":
        return Element(kind, o=0.1 + 0.1 * draws[0], beta=0.2 + 0.2 * draws[1])
    if kind == "deadzone":
        return Element(kind, d=0.1 + 0.15 * draws[0])
    if kind == "tanh":
        return Element(kind, k=1.5 + draws[0])
    if kind == "linear":
        return Element(kind)
    raise ValueError(f"unknown element {kind}")


# --- inputs ---------------------------------------------------------------------------


def multisine(rng: np.random.Generator, n: int, band: Tuple[float, float]) -> np.ndarray:
    """Random-phase multisine with equal amplitudes on the grid ``k / n`` inside ``band``
    (fractions of Nyquist), peak 1."""
    k = np.arange(1, n // 2)
    lines = k[(k / n >= band[0] / 2) & (k / n <= band[1] / 2)]
    t = np.arange(n)
    phases = rng.uniform(0, 2 * np.pi, size=lines.size)
    u = np.cos(2 * np.pi * np.outer(t, lines) / n + phases).sum(axis=1)
    return u / np.abs(u).max()


def filtered_noise(rng: np.random.Generator, n: int, corner: float) -> np.ndarray:
    """Gaussian noise through a 4th-order Butterworth low-pass (corner a fraction of Nyquist),
    peak 1."""
    b, a = signal.butter(4, corner)
    u = signal.lfilter(b, a, rng.standard_normal(n + 500))[500:]
    return u / np.abs(u).max()


def prbs(rng: np.random.Generator, n: int, hold: int) -> np.ndarray:
    """Binary levels -1, +1, each clock tick held ``hold`` samples."""
    ticks = rng.integers(0, 2, size=n // hold + 1) * 2.0 - 1.0
    return np.repeat(ticks, hold)[:n]


def staircase(rng: np.random.Generator, n: int, levels: Tuple[float, float] = (-1.0, 1.0),
              durations: Tuple[int, int] = (50, 300)) -> np.ndarray:
    """Uniform random levels, each held a uniform random number of samples."""
    out: List[float] = []
    while len(out) < n:
        out += [rng.uniform(*levels)] * int(rng.integers(durations[0], durations[1] + 1))
    return np.array(out[:n])


def chirp(rng: np.random.Generator, n: int) -> np.ndarray:
    """Linear chirp of amplitude 1 from 0.001 to 0.2 cycles per sample."""
    t = np.arange(n)
    phi = rng.uniform(0, 360)
    return signal.chirp(t, f0=0.001, t1=n - 1, f1=0.2, method="linear", phi=phi)


def quantised(rng: np.random.Generator, n: int, corner: float, levels: int = 8) -> np.ndarray:
    """Filtered noise rounded to ``levels`` equally spaced levels in [-1, 1]."""
    grid = np.linspace(-1.0, 1.0, levels)
    u = filtered_noise(rng, n, corner)
    return grid[np.abs(u[:, None] - grid[None, :]).argmin(axis=1)]


def input_maker(spec: Spec, rng: np.random.Generator) -> Tuple[Callable[[np.random.Generator], np.ndarray], dict]:
    """The input generator of the spec's kind with its parameters drawn once (shared by both
    parts), and those parameters."""
    n = spec.samples
    kind = spec.input
    if kind == "multisine":
        band = (rng.uniform(0.1, 0.2), rng.uniform(0.3, 0.6))
        return (lambda g: multisine(g, n, band)), {"band": band}
    if kind in ("noise", "quantised"):
        corner = rng.uniform(0.05, 0.3)
        if kind == "noise":
            return (lambda g: filtered_noise(g, n, corner)), {"corner": corner}
        return (lambda g: quantised(g, n, corner)), {"corner": corner, "levels": 8}
    if kind == "prbs":
        hold = int(rng.integers(5, 21))
        return (lambda g: prbs(g, n, hold)), {"hold": hold}
    if kind == "staircase":
        return (lambda g: staircase(g, n)), {}
    if kind == "chirp":
        return (lambda g: chirp(g, n)), {}
    if kind == "closedloop":
        return (lambda g: staircase(g, n, (-0.6, 0.6), (100, 400))), {}
    raise ValueError(f"unknown input {kind}")


# --- noise and loops ------------------------------------------------------------------

AR_POLE = 0.8


def noise_std(y_clean: np.ndarray, snr_db: float, coloured: bool) -> float:
    """The white driving noise's standard deviation that gives ``snr_db`` against
    ``y_clean``'s variance, from the noise process's theoretical variance."""
    gain = 1.0 / (1.0 - AR_POLE**2) if coloured else 1.0
    return float(np.sqrt(np.var(y_clean) / 10 ** (snr_db / 10) / gain))


def make_noise(rng: np.random.Generator, n: int, std: float, coloured: bool) -> np.ndarray:
    """White or AR(1) noise driven by white noise of ``std`` (the AR filter started at its
    stationary state)."""
    w = std * rng.standard_normal(n)
    if not coloured:
        return w
    zi = np.array([w[0] * AR_POLE / np.sqrt(1 - AR_POLE**2)])
    return signal.lfilter([1.0], [1.0, -AR_POLE], w, zi=zi)[0]


def loop_gains(plant: Plant) -> Tuple[float, float]:
    """``(kp, ki)`` of the closed loop: halved from (0.5, 0.1) until the linear loop, the
    element's slope bounded by ``SLOPE_BOUND``, has its poles inside 0.995 (``ki = 0``: P only,
    for an integrating plant)."""
    kp, ki = 0.5, 0.0 if plant.integrating else 0.1
    b = SLOPE_BOUND * plant.num
    for _ in range(30):
        if plant.integrating:
            char = _padd(plant.den, kp * b)
        else:
            char = _padd(np.convolve(plant.den, [1.0, -1.0]), np.convolve(b, [kp + ki, -kp]))
        if np.abs(np.roots(char)).max() < 0.995:
            return kp, ki
        kp, ki = kp / 2, ki / 2
    raise RuntimeError("no stabilising gains")


def _padd(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    n = max(a.size, b.size)
    return np.pad(a, (0, n - a.size)) + np.pad(b, (0, n - b.size))


def closed_loop(plant: Plant, element: Element, r: np.ndarray, gains: Tuple[float, float],
                noise: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The loop run sample by sample: ``(u, y, y_clean)``; ``y_clean`` is the plant's output
    before the measurement noise, ``y = y_clean + noise`` is what the controller sees."""
    kp, ki = gains
    n = r.size
    den = plant.den
    num = np.pad(plant.num, (0, den.size - plant.num.size))
    state = element.start(0.0)
    v0 = state.step(0.0)
    order = den.size - 1
    # Past values of v and y_clean, most recent first; at rest at v0 for a stable plant.
    y_rest = 0.0 if plant.integrating else v0
    vs = [v0] * order
    ys = [y_rest] * order
    u = np.zeros(n)
    y = np.zeros(n)
    yc = np.zeros(n)
    u_prev, e_prev = 0.0, 0.0
    for t in range(n):
        yc[t] = (np.dot(num[1:], vs) - np.dot(den[1:], ys)) / den[0]
        y[t] = yc[t] + noise[t]
        e = r[t] - y[t]
        u[t] = kp * e if plant.integrating else u_prev + kp * (e - e_prev) + ki * e
        u_prev, e_prev = u[t], e
        vs = [state.step(u[t])] + vs[:-1]
        ys = [yc[t]] + ys[:-1]
    return u, y, yc


# --- records --------------------------------------------------------------------------


def make_record(spec: Spec) -> Record:
    """The record of ``spec``: deterministic given ``spec.seed``."""
    rng = np.random.default_rng(spec.seed)
    plant = make_plant(rng, spec.order, spec.plant, spec.integrating)
    element = make_element(rng, spec.element)
    maker, settings = input_maker(spec, rng)
    g_est = np.random.default_rng(rng.integers(2**63))
    g_val = np.random.default_rng(rng.integers(2**63))
    g_noise = np.random.default_rng(rng.integers(2**63))
    n = spec.samples
    first, second = maker(g_est), maker(g_val)
    if spec.input == "closedloop":
        gains = loop_gains(plant)
        quiet = np.zeros(n)
        _, _, clean = closed_loop(plant, element, first, gains, quiet)
        std = noise_std(clean, spec.snr_db, spec.coloured)
        u_est, y_est, yc_est = closed_loop(plant, element, first, gains,
                                           make_noise(g_noise, n, std, spec.coloured))
        u_val, y_val, yc_val = closed_loop(plant, element, second, gains,
                                           make_noise(g_noise, n, std, spec.coloured))
        return Record(spec, plant, element, u_est, y_est, yc_est, u_val, y_val, yc_val, std,
                      r_est=first, r_val=second, gains=gains, settings=settings)
    yc_est = run_plant(plant, element.start(first[0]).run(first))
    yc_val = run_plant(plant, element.start(second[0]).run(second))
    std = noise_std(yc_est, spec.snr_db, spec.coloured)
    y_est = yc_est + make_noise(g_noise, n, std, spec.coloured)
    y_val = yc_val + make_noise(g_noise, n, std, spec.coloured)
    return Record(spec, plant, element, first, y_est, yc_est, second, y_val, yc_val, std,
                  settings=settings)


def _family() -> List[Spec]:
    """35 specs: each input kind with each element, orders 1-6, plants of each kind, SNR
    10-40 dB, a third of them coloured, four integrating."""
    snrs = (10, 20, 30, 40)
    plants = PLANT_KINDS
    specs: List[Spec] = []
    i = 0
    for kind in INPUTS:
        for element in ELEMENTS:
            order = 1 + (i * 5 + 2) % 6
            plant = plants[i % 4] if not (plants[i % 4] == "resonant" and order < 2) else "mixed"
            specs.append(Spec(
                input=kind, order=order, element=element, snr_db=snrs[(i // 2) % 4],
                plant=plant, coloured=i % 3 == 2, integrating=i % 9 == 4,
                samples=2000 + 1000 * ((i * 3) % 5), seed=1000 + i,
            ))
            i += 1
    return specs


FAMILY: List[Spec] = _family()


def family(base: int = 1000) -> List[Spec]:
    """The family with seeds ``base + index``."""
    return [replace(s, seed=base + i) for i, s in enumerate(FAMILY)]
