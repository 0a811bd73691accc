#!/usr/bin/env python3
"""`qrm resources`: the keys promised, finite and positive, and the relations a surface-code plan
must satisfy, for the paper's 8x8 cell.

    check_resources.py QRM

- every key of the issue's list is there, finite and > 0, for the pruned and the unpruned circuit;
- physical_qubits >= logical_qubits * code_distance^2 and t_count >= 4 * toffoli_count;
- the unpruned circuit costs more T gates and time than the pruned one;
- a tighter error budget never lowers the distance, the T-count or the physical qubits;
- the ion preset (p = 1e-4, 100 us) needs a smaller distance but more time than superconducting;
- --image costs one estimate per cell and channel (192 for paper_8x8), summed.
"""
import json
import math
import subprocess
import sys

KEYS = ["logical_qubits", "cnot_count", "toffoli_count", "t_count", "t_depth", "rotation_count",
        "code_distance", "physical_qubits", "seconds_per_a", "seconds_per_estimate"]


def run(qrm, *flags):
    r = subprocess.run([qrm, "resources", "--scene", "paper_8x8", "--x", "3", "--y", "4", "--steps", "3", *flags],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("qrm resources %s: exit %d: %s" % (" ".join(flags), r.returncode, r.stderr))
    return json.loads(r.stdout)


def main():
    qrm = sys.argv[1]
    failures = []
    base = run(qrm)
    for label, c in (("pruned", base), ("unpruned", base["unpruned"])):
        for k in KEYS:
            v = c.get(k)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                failures.append("%s: %s = %r" % (label, k, v))
        if c["physical_qubits"] < c["logical_qubits"] * c["code_distance"] ** 2:
            failures.append("%s: physical_qubits %d < logical %d x d^2" % (label, c["physical_qubits"], c["logical_qubits"]))
        if c["t_count"] < 4 * c["toffoli_count"]:
            failures.append("%s: t_count %d < 4 x %d Toffolis" % (label, c["t_count"], c["toffoli_count"]))
    if not (base["unpruned"]["t_count"] > base["t_count"] and
            base["unpruned"]["seconds_per_estimate"] > base["seconds_per_estimate"]):
        failures.append("the unpruned circuit is not dearer than the pruned one")
    last = None
    for eps in ("0.1", "1e-3", "1e-6", "1e-9"):
        c = run(qrm, "--error", eps)
        now = (c["code_distance"], c["t_count"], c["physical_qubits"])
        if last is not None and any(n < l for n, l in zip(now, last)):
            failures.append("--error %s: (distance, T-count, qubits) %s fell from %s" % (eps, now, last))
        last = now
    img = run(qrm, "--image")["image"]
    # paper_8x8's three channels differ (red and green walls), so every cell costs 3 estimates.
    if img["estimates"] != 3 * 64 or not img["seconds"] >= img["seconds_longest_estimate"] > 0:
        failures.append("--image: %r" % img)
    ion = run(qrm, "--preset", "ion")
    if not (ion["code_distance"] < base["code_distance"] and ion["seconds_per_estimate"] > base["seconds_per_estimate"]):
        failures.append("ion: distance %d (superconducting %d), %g s (superconducting %g s)"
                        % (ion["code_distance"], base["code_distance"], ion["seconds_per_estimate"],
                           base["seconds_per_estimate"]))
    if failures:
        sys.exit("\n".join(failures))
    print("qrm resources: paper_8x8 (3, 4): T-count %d, distance %d, %d physical qubits, %.3g s per estimate "
          "(superconducting); as promised" % (base["t_count"], base["code_distance"], base["physical_qubits"],
                                              base["seconds_per_estimate"]))


if __name__ == "__main__":
    main()
