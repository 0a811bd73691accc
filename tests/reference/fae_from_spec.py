#!/usr/bin/env python3
"""Runs `qrm estimate --estimator fae ... --exact-probabilities --format json` for a grid of cases
and compares each result with FAE written down directly from the FAE rules stated in fae.hpp's header (this file is the
independent reference: plain Python floats, no shared code with the library)."""
import json
import math
import subprocess
import sys


def fae_spec(a, delta, maxiter, rescale):
    """the FAE rules stated in fae.hpp's header, exact-probability mode: returns (theta_lo, theta_hi, estimate, calls)."""
    target = a / 16 if rescale else a
    theta = math.asin(math.sqrt(target))
    n1 = math.floor(1944 * math.log(2 / delta))
    n2 = math.floor(972 * math.log(2 / delta))
    calls = 0

    def c_hat(k, shots):
        nonlocal calls
        calls += (2 * k + 1) * shots
        return 1 - 2 * math.sin((2 * k + 1) * theta) ** 2

    lo, hi = 0.0, math.asin(0.25)
    stage_two, j0, v = False, maxiter, 0.0
    for j in range(1, maxiter + 1):
        K = 2 ** (j + 1) + 2
        if not stage_two:
            c = c_hat(2 ** (j - 1), n1)
            half = math.sqrt(12 * math.log(2 / delta) / n1)
            lo, hi = math.acos(min(1.0, c + half)) / K, math.acos(max(-1.0, c - half)) / K
            if 2 ** (j + 1) * hi >= 3 * math.pi / 8 and j < maxiter:
                j0, v, stage_two = j, 2 ** j * (lo + hi), True
        else:
            c1 = c_hat(2 ** (j - 1), n2)
            c2 = c_hat(2 ** (j - 1) + 2 ** (j0 - 1), n2)
            rho = math.atan2((c1 * math.cos(v) - c2) / math.sin(v), c1)
            n = math.trunc((K * hi - rho + math.pi / 3) / (2 * math.pi))
            lo, hi = (2 * math.pi * n + rho - math.pi / 3) / K, (2 * math.pi * n + rho + math.pi / 3) / K
    scale = 4 if rescale else 1
    return lo, hi, (scale * math.sin((lo + hi) / 2)) ** 2, calls


def close(x, y, tol=1e-12):
    return abs(x - y) <= tol * max(1.0, abs(y))


def main():
    qrm = sys.argv[1]
    failures = 0
    cases = 0
    for a in [0.0, 1e-6, 0.01, 0.05, 0.2, 0.25, 0.3, 0.5, 0.8, 0.99, 1.0]:
        for delta in [0.01, 0.05]:
            for maxiter in [1, 3, 5, 6]:
                for rescale in [True, False]:
                    if not rescale and a > 0.25:
                        continue
                    cmd = [qrm, "estimate", "--estimator", "fae", "--probability", repr(a), "--delta", repr(delta),
                           "--maxiter", str(maxiter), "--rescale" if rescale else "--no-rescale",
                           "--exact-probabilities", "--format", "json"]
                    out = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
                    lo, hi, est, calls = fae_spec(a, delta, maxiter, rescale)
                    tmax, scale = (math.asin(0.25), 4) if rescale else (math.pi / 2, 1)

                    def to_a(t):
                        return 0.0 if t <= 0 else 1.0 if t >= tmax else (scale * math.sin(t)) ** 2

                    want = {"raw_estimate": est, "estimate": min(1.0, est), "lo": to_a(lo), "hi": to_a(hi)}
                    got = {"raw_estimate": out["raw_estimate"], "estimate": out["estimate"],
                           "lo": out["confidence_interval"][0], "hi": out["confidence_interval"][1]}
                    cases += 1
                    bad = [k for k in want if not close(got[k], want[k])]
                    if out["oracle_calls"] != calls:
                        bad.append("oracle_calls")
                    if bad:
                        failures += 1
                        print("MISMATCH", " ".join(cmd[2:]), bad, got, want, out["oracle_calls"], calls)
    print(f"{cases} cases, {failures} mismatches")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
