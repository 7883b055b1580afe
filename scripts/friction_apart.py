"""Records of a mass on a spring with Coulomb friction, generated apart from the project's
tests (numpy's generator, its own levels and noise draws), diagnosed by the command line.

The mass is the one of docs/friction.md: m = 0.01, k = 1, c = 0.06, F_c = 0.15 under a sign
smoothed over eps = 0.02, integrated by RK4 at 20 steps a sample (ts = 0.01 s), driven by
levels in [-1, 1] held 20-80 samples through a first-order low-pass after a hold of 100
samples at -1, its position measured with white noise at 30 dB. Each seed's record is
diagnosed with the record of seed + 1000 as validation:

    hsid diagnose --umin -1 --umax 1 --hold 100 --nonlinearity static --segments 6 --order 2

Usage: python scripts/friction_apart.py HSID_BINARY OUT_DIR [SEEDS...] (default seeds 1-5).
Prints per seed the effects added, the friction step's Coulomb force and the validation RMSE
before, after the friction step and after the last step.
"""

import json
import subprocess
import sys

import numpy as np

HOLD, LEN, SNR_DB = 100, 3000, 30.0
M, K, C, FC, EPS = 0.01, 1.0, 0.06, 0.15, 0.02


def record(seed):
    rng = np.random.default_rng(seed)
    u = [-1.0] * HOLD
    s = -1.0
    while len(u) < HOLD + LEN:
        level = rng.uniform(-1.0, 1.0)
        for _ in range(int(rng.integers(20, 81))):
            s = 0.8 * s + 0.2 * level
            u.append(s)
    u = np.array(u[: HOLD + LEN])

    def acc(x, v, f):
        return (f - K * x - C * v - FC * np.tanh(v / EPS)) / M

    x, v, h = -1.0 / K, 0.0, 0.01 / 20
    clean = np.empty_like(u)
    for t, f in enumerate(u):
        clean[t] = x
        for _ in range(20):
            k1 = (v, acc(x, v, f))
            k2 = (v + 0.5 * h * k1[1], acc(x + 0.5 * h * k1[0], v + 0.5 * h * k1[1], f))
            k3 = (v + 0.5 * h * k2[1], acc(x + 0.5 * h * k2[0], v + 0.5 * h * k2[1], f))
            k4 = (v + h * k3[1], acc(x + h * k3[0], v + h * k3[1], f))
            x += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            v += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    sd = np.sqrt(clean.var() / 10 ** (SNR_DB / 10))
    return u, clean + sd * rng.standard_normal(len(u))


def write(path, u, y):
    np.savetxt(path, np.column_stack([u, y]), delimiter=",", header="u,y", comments="")


def main(hsid, out, seeds):
    for seed in seeds:
        est, val = f"{out}/est{seed}.csv", f"{out}/val{seed}.csv"
        write(est, *record(seed))
        write(val, *record(seed + 1000))
        report = f"{out}/diagnosis{seed}.json"
        subprocess.run(
            [hsid, "diagnose", "--data", est, "--validation", val, "--validation-skip",
             str(HOLD), "--umin", "-1", "--umax", "1", "--hold", str(HOLD),
             "--nonlinearity", "static", "--segments", "6", "--order", "2",
             "--json", report],
            check=True, stdout=subprocess.DEVNULL)
        with open(report) as fh:
            d = json.load(fh)
        steps = [e for e in d["effects"] if e["added"]]
        added = ", ".join(e["name"] for e in steps) or "-"
        fr = [e for e in steps if e["name"] == "friction"]
        line = f"seed {seed}: added {added}; validation RMSE {d['error_before']:.4f}"
        if fr:
            coulomb = (d["model_after"]["model"].get("friction") or {}).get("coulomb")
            line += f" -> {fr[0]['error_after']:.4f} by friction (Coulomb {coulomb:.4f})"
        line += f", after the last step {d['error_after']:.4f}"
        print(line, flush=True)


if __name__ == "__main__":
    seeds = [int(s) for s in sys.argv[3:]] or [1, 2, 3, 4, 5]
    main(sys.argv[1], sys.argv[2], seeds)
