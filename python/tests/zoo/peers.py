"""Linear peers on the same record as `hsid.identify`: an output-error model fitted by
simulation error with scipy, and nfoursid's subspace identification.

Both models are linear, from the input ``u`` to the output ``y``, and both are simulated the
same way on the validation part: from rest at the part's first input ``u[0]``, plus an output
level fitted on the estimation part, i.e. ``y_hat = k + G(1) u[0] + G(q) (u - u[0])`` with
``G``'s state zero at the start (``k`` the output at rest at ``u = 0``). The records of a stable
plant start at rest at their first input (records.py), so this is the initial state the true
plant has. Scored by ``nrmse``.

* ``fit_oe``: ``G = B(q) / F(q)``, ``B(q) = b1 q^-1 + ... + bn q^-n`` (a delay of 1),
  ``F(q) = 1 + f1 q^-1 + ... + fn q^-n``, and the level ``c``; started from the ARX
  least-squares fit of the same order (with a constant), then ``scipy.optimize.least_squares``
  on the simulation error of the estimation part (at most 300 evaluations). ``F`` is kept stable by reflecting its roots
  outside the unit circle into it (``1 / conj(r)``) and clipping their modulus at 0.999, both
  at the start and inside every evaluation. Orders 1-6, the smallest BIC
  ``N ln(V) + (2n + 1) ln N`` (``V`` the mean squared simulation error on the estimation part)
  wins.
* ``fit_nfoursid``: nfoursid's ``NFourSID`` on the mean-removed estimation part
  (``num_block_rows = 20``), ``system_identification(rank=n)`` for n = 1-6, its ``(A, B, C, D)``
  simulated as above (``k`` the output mean minus ``G(1)`` times the input mean), the smallest BIC of the simulation error (``n^2 + 2n + 1`` parameters) wins.
  Its state-space model is simulated as it is; an unstable ``A`` is not repaired (a peer is
  scored as it comes).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
from scipy import optimize, signal

MAX_ORDER = 6
MAX_MODULUS = 0.999


def nrmse(y: np.ndarray, y_hat: np.ndarray) -> float:
    """``||y - y_hat|| / ||y - mean(y)||``."""
    return float(np.linalg.norm(y - y_hat) / np.linalg.norm(y - np.mean(y)))


@dataclass
class LinearModel:
    """``y_hat = k + G(1) u[0] + G(q) (u - u[0])`` from zero state, ``G = num(q) / den(q)``."""

    num: np.ndarray
    den: np.ndarray
    k: float
    order: int

    @property
    def gain(self) -> float:
        """``G(1)``."""
        return float(np.sum(self.num) / np.sum(self.den))

    def simulate(self, u: np.ndarray) -> np.ndarray:
        """The output for ``u``, from rest at ``u[0]``."""
        return self.k + self.gain * u[0] + signal.lfilter(self.num, self.den, u - u[0])


def stabilise(den: np.ndarray) -> np.ndarray:
    """``den`` with its roots outside the unit circle reflected inside and every root's
    modulus at most ``MAX_MODULUS``."""
    roots = np.roots(den)
    if roots.size == 0:
        return den
    big = np.abs(roots) > 1.0
    roots[big] = 1.0 / np.conj(roots[big])
    mod = np.abs(roots)
    over = mod > MAX_MODULUS
    roots[over] = roots[over] / mod[over] * MAX_MODULUS
    return np.real(np.poly(roots)) * den[0]


def _arx(u: np.ndarray, y: np.ndarray, n: int) -> np.ndarray:
    """ARX least squares ``y(t) = -sum f_i y(t-i) + sum b_i x(t-i) + a`` on ``x = u - u[0]``:
    the parameter vector ``(b, f, k)`` of the OE model, ``k = a / F(1) - G(1) u[0]``."""
    x = u - u[0]
    rows = np.arange(n, y.size)
    phi = np.column_stack(
        [x[rows - i] for i in range(1, n + 1)] + [-y[rows - i] for i in range(1, n + 1)]
        + [np.ones(rows.size)]
    )
    theta, *_ = np.linalg.lstsq(phi, y[rows], rcond=None)
    b, f, k = theta[:n], theta[n:2 * n], theta[-1]
    den = stabilise(np.concatenate([[1.0], f]))
    level = k / np.sum(den) if abs(np.sum(den)) > 1e-6 else float(np.mean(y))
    level -= np.sum(b) / np.sum(den) * u[0]
    return np.concatenate([b, den[1:], [level]])


def _model(theta: np.ndarray, n: int) -> LinearModel:
    b, f, k = theta[:n], theta[n:2 * n], theta[-1]
    den = stabilise(np.concatenate([[1.0], f]))
    return LinearModel(np.concatenate([[0.0], b]), den, float(k), n)


def fit_oe_order(u: np.ndarray, y: np.ndarray, n: int) -> LinearModel:
    """The OE model of order ``n`` fitted by simulation error from the ARX start."""
    start = _arx(u, y, n)
    result = optimize.least_squares(
        lambda th: _model(th, n).simulate(u) - y, start, method="trf", x_scale="jac", max_nfev=300,
    )
    return _model(result.x, n)


def bic(u: np.ndarray, y: np.ndarray, model: "LinearModel", params: int) -> float:
    """``N ln(V) + params ln N`` of the simulation error on ``(u, y)``."""
    e = y - model.simulate(u)
    return float(y.size * np.log(np.mean(e**2)) + params * np.log(y.size))


def fit_oe(u: np.ndarray, y: np.ndarray, orders: range = range(1, MAX_ORDER + 1)) -> LinearModel:
    """The OE model whose order (among ``orders``) has the smallest BIC."""
    best: Optional[LinearModel] = None
    best_bic = np.inf
    for n in orders:
        model = fit_oe_order(u, y, n)
        score = bic(u, y, model, 2 * n + 1)
        if score < best_bic:
            best, best_bic = model, score
    assert best is not None
    return best


def fit_nfoursid(u: np.ndarray, y: np.ndarray, orders: range = range(1, MAX_ORDER + 1),
                 block_rows: int = 20) -> LinearModel:
    """nfoursid's model whose rank (among ``orders``) has the smallest BIC, as a
    ``LinearModel``."""
    import pandas as pd
    from nfoursid.nfoursid import NFourSID

    u_mean, y_mean = float(np.mean(u)), float(np.mean(y))
    frame = pd.DataFrame({"u": u - u_mean, "y": y - y_mean})
    n4 = NFourSID(frame, output_columns=["y"], input_columns=["u"], num_block_rows=block_rows)
    n4.subspace_identification()
    best: Optional[LinearModel] = None
    best_bic = np.inf
    for n in orders:
        ss, _ = n4.system_identification(rank=n)
        num, den = signal.ss2tf(ss.a, ss.b, ss.c, ss.d)
        num = np.ravel(num)
        gain = np.sum(num) / np.sum(den) if abs(np.sum(den)) > 1e-9 else 0.0
        model = LinearModel(num, den, y_mean - gain * u_mean, n)
        with np.errstate(all="ignore"):
            score = bic(u, y, model, n * n + 2 * n + 1)
        if np.isfinite(score) and score < best_bic:
            best, best_bic = model, score
    if best is None:
        raise RuntimeError("nfoursid: no rank gave a finite simulation error")
    return best
