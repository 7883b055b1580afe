"""Runs nfoursid on the (z(t), ybar(t)) records exported by hsid and compares the poles and the
time with hsid's own estimate on the same runs. Called by scripts/compare-nfoursid.sh."""

import json
import sys
import time

import numpy as np
import pandas as pd
from nfoursid.nfoursid import NFourSID


def upper(poles):
    """The pole with the largest imaginary part."""
    return max(poles, key=lambda p: p[1])


def main(out_dir):
    with open(f"{out_dir}/hsid.json") as fh:
        hsid = json.load(fh)
    rows = []
    for run in hsid["runs"]:
        df = pd.read_csv(run["csv"])
        inputs = [c for c in df.columns if c.startswith("z")]
        start = time.perf_counter()
        n4 = NFourSID(df, output_columns=["ybar"], input_columns=inputs,
                      num_block_rows=hsid["f"])
        n4.subspace_identification()
        ss, _ = n4.system_identification(rank=run["order"])
        seconds = time.perf_counter() - start
        ev = np.linalg.eigvals(ss.a)
        p_n4 = upper([(float(e.real), float(e.imag)) for e in ev])
        p_hs = upper([tuple(p) for p in run["poles"]])
        rows.append((run["run"], p_hs, p_n4, run["seconds"], seconds))

    print(f"case {hsid['case']}: hsid {hsid['method']} vs nfoursid "
          f"(PO-MOESP instruments, N4SID state sequence), f = p = {hsid['f']}, "
          f"{len(rows)} runs, {len(df.columns) - 1} regressor channels")
    print(f"{'run':>4} {'hsid pole':>22} {'nfoursid pole':>22} {'|diff|':>9} "
          f"{'hsid ms':>9} {'nfoursid ms':>12}")
    for r, ph, pn, th, tn in rows:
        d = abs(complex(*ph) - complex(*pn))
        print(f"{r:>4} {ph[0]:>10.5f}{ph[1]:>+10.5f}j {pn[0]:>10.5f}{pn[1]:>+10.5f}j "
              f"{d:>9.5f} {1e3 * th:>9.2f} {1e3 * tn:>12.1f}")
    hs = np.array([complex(*r[1]) for r in rows])
    n4 = np.array([complex(*r[2]) for r in rows])
    diff = hs - n4
    k = len(rows)
    # Spread of each estimator over the runs (re and im together).
    s_hs = np.sqrt(np.var(hs.real, ddof=1) + np.var(hs.imag, ddof=1))
    s_n4 = np.sqrt(np.var(n4.real, ddof=1) + np.var(n4.imag, ddof=1))
    mean_diff = abs(diff.mean())
    se_mean = np.sqrt((np.var(diff.real, ddof=1) + np.var(diff.imag, ddof=1)) / k)
    rms_diff = np.sqrt(np.mean(np.abs(diff) ** 2))
    t_hs = np.median([r[3] for r in rows])
    t_n4 = np.median([r[4] for r in rows])
    print()
    print(f"pole spread over the runs: hsid {s_hs:.5f}, nfoursid {s_n4:.5f}")
    print(f"pole difference: RMS {rms_diff:.5f} = {rms_diff / s_hs:.2f} x hsid's spread; "
          f"mean {mean_diff:.5f} = {mean_diff / se_mean:.2f} standard errors")
    agree = mean_diff <= 3 * se_mean and rms_diff <= 2 * max(s_hs, s_n4)
    print("agreement: " + ("yes" if agree else "NO") +
          " (mean difference within 3 standard errors and RMS difference within twice "
          "the larger spread)")
    print(f"median time per identification: hsid {1e3 * t_hs:.2f} ms, "
          f"nfoursid {1e3 * t_n4:.1f} ms: hsid is {t_n4 / t_hs:.0f}x faster")
    return 0 if agree else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
