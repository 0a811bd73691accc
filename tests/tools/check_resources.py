#!/usr/bin/env python3
"""`qrm resources`: the keys promised, finite and positive, and the relations a surface-code plan
must satisfy, for the paper's 8x8 cell.

    check_resources.py QRM

- every key of the issue's list is there, finite and > 0, for the pruned and the unpruned circuit;
- physical_qubits >= logical_qubits * code_distance^2 and t_count >= 4 * toffoli_count;
- the unpruned circuit costs more T gates and time than the pruned one;
- a tighter error budget never lowers the distance, the T-count or the physical qubits;
- the ion preset (p = 1e-4, 100 us) needs a smaller distance but more time than superconducting;
- --image costs one estimate per cell and channel (192 for paper_8x8), summed;
- a 3D pixel (the 8^3 Cornell box, walked as qrm render --method quantum) gets the same keys and
  relations, and its --image one estimate per distinct pixel start and channel;
- --width on a 2D scene is refused (exit 2, naming the flag).
"""
import json
import math
import subprocess
import sys

KEYS = ["logical_qubits", "cnot_count", "toffoli_count", "t_count", "t_depth", "rotation_count",
        "code_distance", "physical_qubits", "seconds_per_a", "seconds_per_estimate"]


def run_args(qrm, *args):
    r = subprocess.run([qrm, "resources", *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("qrm resources %s: exit %d: %s" % (" ".join(args), r.returncode, r.stderr))
    return json.loads(r.stdout)


def run(qrm, *flags):
    return run_args(qrm, "--scene", "paper_8x8", "--x", "3", "--y", "4", "--steps", "3", *flags)


def check_plan(label, c, failures):
    for k in KEYS:
        v = c.get(k)
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            failures.append("%s: %s = %r" % (label, k, v))
    if c["physical_qubits"] < c["logical_qubits"] * c["code_distance"] ** 2:
        failures.append("%s: physical_qubits %d < logical %d x d^2" % (label, c["physical_qubits"], c["logical_qubits"]))
    if c["t_count"] < 4 * c["toffoli_count"]:
        failures.append("%s: t_count %d < 4 x %d Toffolis" % (label, c["t_count"], c["toffoli_count"]))


def main():
    qrm = sys.argv[1]
    failures = []
    base = run(qrm)
    for label, c in (("pruned", base), ("unpruned", base["unpruned"])):
        check_plan(label, c, failures)
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
    pixel = run_args(qrm, "--scene", "cornell", "--width", "16", "--height", "16", "--steps", "4", "--image")
    check_plan("cornell pixel (8, 8)", pixel, failures)
    if pixel.get("voxels") != 8 or pixel.get("march") != "surface":
        failures.append("cornell pixel: voxels %r, march %r (expected the CLI's defaults, 8 and surface)"
                        % (pixel.get("voxels"), pixel.get("march")))
    pimg = pixel["image"]
    if not (0 < pimg["distinct_starts"] <= 256 and pimg["estimates"] == 3 * pimg["distinct_starts"]
            and pimg["seconds"] >= pimg["seconds_longest_estimate"] > 0):
        failures.append("cornell --image: %r" % pimg)
    bad = subprocess.run([qrm, "resources", "--scene", "paper_8x8", "--width", "16"], capture_output=True, text=True)
    if bad.returncode != 2 or "--width applies to 3D scenes" not in bad.stderr:
        failures.append("--width on paper_8x8: exit %d, %r" % (bad.returncode, bad.stderr))
    if failures:
        sys.exit("\n".join(failures))
    print("qrm resources: paper_8x8 (3, 4): T-count %d, distance %d, %d physical qubits, %.3g s per estimate "
          "(superconducting); as promised" % (base["t_count"], base["code_distance"], base["physical_qubits"],
                                              base["seconds_per_estimate"]))
    print("qrm resources: cornell 8^3, pixel (8, 8) of 16x16, 4 bounces: T-count %d, distance %d, %.3g s per estimate; "
          "the image: %d distinct starts, %d estimates, %.3g s" % (pixel["t_count"], pixel["code_distance"],
                                                                 pixel["seconds_per_estimate"], pimg["distinct_starts"],
                                                                 pimg["estimates"], pimg["seconds"]))


if __name__ == "__main__":
    main()
