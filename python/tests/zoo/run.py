"""The zoo as a measuring instrument: `hsid.identify`'s default on every record of
`records.FAMILY`, beside the linear peers of `peers.py`, scored on the validation part.

    python python/tests/zoo/run.py --out FILE.md [--base 1000] [--only NAME ...]

For each record:

* hsid: ``hsid.identify(u, y, umin=min(u), umax=max(u), hold=0)`` on the estimation part, the
  interval from the data as a new user would give it, every other setting its default (an
  integrating plant too). A refusal is recorded as the exception's class and the head of its
  message. A model is simulated on the validation input with ``Model.simulate``, which starts
  at rest at ``u_min``: a hold of ``PREFIX`` samples at the validation part's first input is
  put before it and its output dropped, so the model starts at rest at ``u[0]`` as the record
  does (an integrating model is simulated without the hold, from its rest at ``u_min``, since
  a hold away from its balance point ramps). A validation input outside ``[umin, umax]`` is
  simulated as ``Model.simulate`` does by default, on the borders extended linearly beyond the
  interval, and the count of such inputs is given beside the NRMSE; should ``simulate`` refuse
  (``strict_interval``), that is its own outcome (``out of range``) and the NRMSE of the same
  model on the validation input clipped to the interval is given, labelled ``clipped``.
* the linear OE peer and nfoursid (peers.py), simulated from rest at ``u[0]``;
* the noise floor: the NRMSE of the noise-free validation output against the noisy one.

NRMSE is ``||y_val - y_hat|| / ||y_val - mean(y_val)||``. The summary counts refusals on
records whose output responds (noise-free output's variance above the noise's, SNR > 0 dB),
records where hsid's NRMSE is at most 1.02 times the OE peer's, and records within 1.15 times
the noise floor (clipped NRMSEs are not counted as within).
"""

from __future__ import annotations

import argparse
import re
import pathlib
import sys
import time
import warnings
from collections import Counter
from dataclasses import dataclass
from typing import Iterable, List, Optional, TextIO, Tuple

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import hsid  # noqa: E402
from zoo import peers, records  # noqa: E402

PREFIX = 2000
COMMAND = "python python/tests/zoo/run.py --out FILE.md"


@dataclass
class Row:
    """One record's outcome: hsid's, the peers' and the noise floor."""

    name: str
    outcome: str  # "model", "refused", "out of range"
    detail: str  # the refusal's class and message head, or empty
    hsid: Optional[float]  # validation NRMSE (clipped input for "out of range")
    order: Optional[int]
    oe: float
    oe_order: int
    n4: Optional[float]
    n4_order: Optional[int]
    floor: float
    responds: bool
    seconds: float

    @property
    def ratio(self) -> Optional[float]:
        """hsid's NRMSE over the OE peer's, for a model simulated on the validation input as
        it is."""
        return self.hsid / self.oe if self.outcome == "model" and self.hsid is not None else None

    @property
    def clipped_ratio(self) -> Optional[float]:
        """The same with the validation input clipped to the interval ("out of range" only)."""
        return self.hsid / self.oe if self.outcome == "out of range" and self.hsid is not None else None


def head(error: BaseException, width: int = 90) -> str:
    """The exception's class and the head of its message's first line."""
    text = str(error).splitlines()[0] if str(error) else ""
    text = text if len(text) <= width else text[: width - 1] + "…"
    return f"{type(error).__name__}: {text}"


def simulate_hsid(model: "hsid.Model", u: np.ndarray) -> np.ndarray:
    """The model's output for ``u``, from rest at ``u[0]`` (see the module docstring)."""
    if model.integrating:
        return model.simulate(u)
    held = np.concatenate([np.full(PREFIX, u[0]), u])
    return model.simulate(held)[PREFIX:]


def score(rec: records.Record, with_nfoursid: bool = True,
          orders: range = range(1, peers.MAX_ORDER + 1)) -> Row:
    """Runs hsid and the peers on ``rec`` (the peers' orders among ``orders``)."""
    start = time.time()
    u, y, uv, yv = rec.u_est, rec.y_est, rec.u_val, rec.y_val
    umin, umax = float(np.min(u)), float(np.max(u))
    outcome, detail, nr, order = "model", "", None, None
    try:
        model = hsid.identify(u, y, umin=umin, umax=umax, hold=0)
    except hsid.HsidError as error:
        outcome, detail = "refused", head(error)
    else:
        order = model.order
        try:
            # Model.simulate extends the borders beyond the interval and warns; counted here.
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                nr = peers.nrmse(yv, simulate_hsid(model, uv))
            outside = int(np.sum((uv < umin) | (uv > umax)))
            if outside:
                detail = f"{outside} of {len(uv)} validation inputs outside the interval, borders extended"
        except hsid.DataError as error:
            outcome, detail = "out of range", head(error)
            nr = peers.nrmse(yv, simulate_hsid(model, np.clip(uv, umin, umax)))
    oe = peers.fit_oe(u, y, orders)
    n4 = peers.fit_nfoursid(u, y, orders) if with_nfoursid else None
    responds = bool(np.var(rec.y_est_clean) > np.var(y - rec.y_est_clean))
    return Row(
        name=rec.name, outcome=outcome, detail=detail, hsid=nr, order=order,
        oe=peers.nrmse(yv, oe.simulate(uv)), oe_order=oe.order,
        n4=None if n4 is None else peers.nrmse(yv, n4.simulate(uv)),
        n4_order=None if n4 is None else n4.order,
        floor=peers.nrmse(yv, rec.y_val_clean), responds=responds,
        seconds=time.time() - start,
    )


def run(specs: Iterable[records.Spec], with_nfoursid: bool = True, log: Optional[TextIO] = None,
        orders: range = range(1, peers.MAX_ORDER + 1)) -> List[Row]:
    """One row per spec, in order; progress to ``log``."""
    rows = []
    for spec in specs:
        rows.append(score(records.make_record(spec), with_nfoursid, orders))
        if log is not None:
            r = rows[-1]
            print(f"{r.name}: {r.outcome} {r.hsid} OE {r.oe:.4f} ({r.seconds:.0f} s)", file=log, flush=True)
    return rows


def _num(x: Optional[float], order: Optional[int] = None) -> str:
    if x is None:
        return "—"
    text = f"{x:.3f}" if x < 100 else f"{x:.3g}"
    return text if order is None else f"{text} (n={order})"


def hsid_cell(row: Row) -> str:
    """hsid's column: its NRMSE, or the refusal, or the out-of-range outcome."""
    detail = row.detail.replace("|", "\\|")
    if row.outcome == "refused":
        return f"refused: {detail}"
    if row.outcome == "model" and row.detail:
        return f"{_num(row.hsid, row.order)} ({row.detail})"
    if row.outcome == "out of range":
        return f"simulate refused (validation input out of range); clipped: {_num(row.hsid, row.order)}"
    return _num(row.hsid, row.order)


def refusal_kinds(rows: List[Row]) -> List[Tuple[str, int]]:
    """The refusals grouped by the class and the message's first clause, numbers and the
    path's name dropped, most frequent first."""

    def kind(detail: str) -> str:
        text = re.sub(r"\b(ascending|descending) path: ", "", re.sub(r"\d+(\.\d+)?", "#", detail))
        text = ": ".join(text.split(": ")[:2]).rstrip("…")
        return text if len(text) <= 75 else text[: text.rfind(" ", 0, 75)] + " …"

    kinds = Counter(kind(r.detail) for r in rows)
    return sorted(kinds.items(), key=lambda kv: (-kv[1], kv[0]))


def summary(rows: List[Row]) -> List[str]:
    """The summary lines."""
    n = len(rows)
    refused = [r for r in rows if r.outcome == "refused" and r.responds]
    out_of_range = [r for r in rows if r.outcome == "out of range"]
    ratios = [r.ratio for r in rows if r.ratio is not None]
    clipped = [r.clipped_ratio for r in rows if r.clipped_ratio is not None]
    within = [r for r in rows if r.outcome == "model" and r.hsid <= 1.15 * r.floor]
    within_clipped = [r for r in rows if r.outcome == "out of range" and r.hsid <= 1.15 * r.floor]
    oe_within = [r for r in rows if r.oe <= 1.15 * r.floor]
    n4_within = [r for r in rows if r.n4 is not None and r.n4 <= 1.15 * r.floor]
    lines = [
        f"- records: {n}; the output responds (SNR > 0 dB) on {sum(r.responds for r in rows)}",
        f"- hsid refused {len(refused)}/{n} records whose output responds",
        *[f"  - {count}× {kind}" for kind, count in refusal_kinds(refused)],
        f"- hsid's model refused the validation input (outside [min(u), max(u)] of the estimation part): {len(out_of_range)}/{n}",
        f"- hsid/OE ratio ≤ 1.02: {sum(x <= 1.02 for x in ratios)}/{n}"
        + f" (of the {len(ratios)} models simulated on the validation input as it is); with the input"
        f" clipped: {sum(x <= 1.02 for x in clipped)}/{len(clipped)} more, not counted",
        f"- within 1.15× the noise floor: hsid {len(within)}/{n} (clipped: {len(within_clipped)} more, not"
        f" counted), linear OE {len(oe_within)}/{n}, nfoursid {len(n4_within)}/{n}",
    ]
    return lines


def table(rows: List[Row], base: int) -> str:
    """The markdown table and its summary."""
    out = [
        f"Records of `records.family({base})` (seed of record i: {base} + i); NRMSE on the validation part, (n=…) the model's order.",
        "",
        "| record | hsid outcome / NRMSE | linear OE | nfoursid | noise floor | hsid/OE |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        ratio = "—" if r.ratio is None else f"{r.ratio:.3f}"
        if r.clipped_ratio is not None:
            ratio = f"clipped: {r.clipped_ratio:.3f}"
        out.append(
            f"| {r.name} | {hsid_cell(r)} | {_num(r.oe, r.oe_order)} | {_num(r.n4, r.n4_order)} "
            f"| {r.floor:.3f} | {ratio} |"
        )
    out += ["", *summary(rows), ""]
    return "\n".join(out)


def main(argv: Optional[List[str]] = None) -> int:
    """The command line: runs the family (or ``--only`` names) and writes the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="markdown file to write")
    parser.add_argument("--base", type=int, default=1000, help="seed of the first record")
    parser.add_argument("--only", nargs="*", default=None, help="record names to run")
    args = parser.parse_args(argv)
    specs = records.family(args.base)
    if args.only:
        specs = [s for s in specs if s.name in args.only]
    rows = run(specs, log=sys.stderr)
    pathlib.Path(args.out).write_text(table(rows, args.base))
    return 0


if __name__ == "__main__":
    sys.exit(main())
