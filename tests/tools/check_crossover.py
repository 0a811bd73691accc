#!/usr/bin/env python3
"""`qrm crossover`: the table, the plot and the summary, and the physics they must show.

    check_crossover.py QRM CHECK_SVG WORKDIR

- crossover.csv, crossover.md and crossover.svg are written; the SVG passes check_svg.py with at
  least 8 polylines (Monte Carlo, 3 estimators x 2 presets, the extended fits);
- Monte Carlo's time grows as 1/eps^2: fitted slope in [-2.3, -1.7] (its RMS error is
  sigma/sqrt(N) and its time N * t_path; 8 path counts x 24 repetitions);
- amplitude estimation's projected time grows as about 1/eps: every slope in [-1.5, -0.7];
- so every estimator on every preset crosses Monte Carlo at some eps* below the largest error
  measured;
- a 3D Cornell-box pixel (8^3) gives its report too.
"""
import csv
import json
import math
import os
import subprocess
import sys


def main():
    qrm, check_svg, work = sys.argv[1:4]
    out = os.path.join(work, "crossover")
    r = subprocess.run([qrm, "crossover", "--repetitions", "24", "--out", out, "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("qrm crossover: exit %d: %s" % (r.returncode, r.stderr))
    summary = json.loads(r.stdout)
    failures = []
    for f in ("crossover.csv", "crossover.md", "crossover.svg"):
        if not os.path.isfile(os.path.join(out, f)):
            failures.append("missing " + f)
    s = subprocess.run([sys.executable, check_svg, os.path.join(out, "crossover.svg"), "--min-count", "polyline=8"],
                       capture_output=True, text=True)
    if s.returncode != 0:
        failures.append("crossover.svg: " + s.stdout + s.stderr)
    rows = list(csv.DictReader(open(os.path.join(out, "crossover.csv"))))
    mc = [(float(x["rmse"]), float(x["seconds"])) for x in rows if x["method"] == "mc"]
    if not -2.3 <= summary["mc_slope"] <= -1.7:
        failures.append("Monte Carlo slope %g, expected about -2" % summary["mc_slope"])
    largest = max(e for e, _ in mc)
    for c in summary["crossovers"]:
        name = "%s on %s" % (c["estimator"], c["platform"])
        if not -1.5 <= c["slope"] <= -0.7:
            failures.append("%s: slope %g, expected about -1" % (name, c["slope"]))
        eps = c.get("crossover_eps")
        if not (isinstance(eps, float) and 0 < eps < largest):
            failures.append("%s: crossover eps %r" % (name, eps))
    # 3D: a Cornell-box pixel, from its first hit (the report and a crossing for every estimator).
    out3 = os.path.join(work, "crossover_3d")
    r3 = subprocess.run([qrm, "crossover", "--scene", "cornell", "--repetitions", "8", "--out", out3, "--quiet"],
                        capture_output=True, text=True)
    if r3.returncode != 0:
        failures.append("3D: exit %d: %s" % (r3.returncode, r3.stderr))
    else:
        s3 = json.loads(r3.stdout)
        if s3["scene"] != "cornell_box_8" or len(s3["crossovers"]) != 6 or \
                not os.path.isfile(os.path.join(out3, "crossover.svg")):
            failures.append("3D: unexpected summary %s" % r3.stdout[:300])
    if failures:
        sys.exit("\n".join(failures))
    best = max(summary["crossovers"], key=lambda c: c["crossover_eps"])
    print("crossover: Monte Carlo slope %.2f; earliest crossing %s on %s at eps %.3g (%.3g s per estimate)"
          % (summary["mc_slope"], best["estimator"], best["platform"], best["crossover_eps"], best["seconds_at_crossover"]))


if __name__ == "__main__":
    main()
