#!/usr/bin/env python3
"""Participating media through the qrm tool.

    check_render_media.py QRM WORKDIR

1. Beer-Lambert on the discrete medium. A scene written here: an 8^3 grid whose layers z = 2..5
   are fog (density P, rho R), z = 6 an emitting wall (Le 1, rho 0) facing -z, z = 1 and z = 7
   black boundary layers (nothing comes back around the wrapping grid), seen along +z by a
   camera on the axis of voxel column (3, 3), with the 6 cube directions. The centre pixel's walk
   starts in the first fog voxel going +z; with --steps 4 only the straight path reaches the wall
   (each step moves one voxel and the wall is 4 moves away), so the pixel must be the
   transmittance of 4 fog voxels, ((1 - P) R)^4, to float precision (the PFM stores float32:
   relative 1e-6). With --steps 8, light scattered back into the beam adds to it: strictly more.
2. Monte Carlo converges to the exact image on cornell_fog at the CLI's default size (8^3,
   128x128, 64 directions, 6 bounces): the least-squares slope of log RMSE over log N for
   N = 8, 32, 128, 512 paths per pixel lies in [-0.6, -0.4] (N^-1/2).
"""
import array
import json
import math
import os
import shutil
import subprocess
import sys
import time


def run(qrm, args, out):
    shutil.rmtree(out, ignore_errors=True)
    r = subprocess.run([qrm, "render", *args, "--out", out, "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("qrm render %s failed (%d):\n%s" % (" ".join(args), r.returncode, r.stderr))
    return json.loads(r.stdout)


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            sys.exit("%s: not a colour PFM" % path)
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        a = array.array("f")
        a.frombytes(f.read())
    if scale > 0:
        a.byteswap()
    if len(a) != 3 * w * h:
        sys.exit("%s: %d values for %dx%d" % (path, len(a), w, h))
    # PFM rows run bottom to top.
    return w, h, lambda x, y: a[3 * ((h - 1 - y) * w + x):3 * ((h - 1 - y) * w + x) + 3]


SLAB = """qrm-scene 1
name fog_slab
dims 3
size 8
march surface
fill 0 0 1 7 7 1 B 0 0 1 rho 0 0 0
fill 0 0 2 7 7 5 M density {p} rho {r} {r} {r}
fill 0 0 6 7 7 6 L 0 0 -1 rho 0 0 0 le 1 1 1
fill 0 0 7 7 7 7 B 0 0 -1 rho 0 0 0
camera position 3.5 3.5 -5 look_at 3.5 3.5 7 fov 10
"""


def check_beer_lambert(qrm, work, failures):
    for p, r in ((0.2, 0.9), (0.5, 1.0), (0.0, 0.7)):
        path = os.path.join(work, "fog_slab.txt")
        with open(path, "w") as f:
            f.write(SLAB.format(p=p, r=r))
        values = []
        for steps in (4, 8):
            out = os.path.join(work, "slab%d" % steps)
            run(qrm, ["--scene", path, "--method", "exact", "--directions", "6", "--width", "3", "--height", "3",
                      "--steps", str(steps)], out)
            _, _, img = read_pfm(os.path.join(out, "fog_slab_exact.pfm"))
            values.append(img(1, 1)[0])
        want = ((1 - p) * r) ** 4
        print("fog slab, density %.2f, rho %.2f: centre pixel %.7f with 4 steps (Beer-Lambert ((1 - P) R)^4 = %.7f), "
              "%.7f with 8" % (p, r, values[0], want, values[1]))
        if not abs(values[0] - want) <= 1e-6 * want:
            failures.append("fog slab (%.2f, %.2f): transmittance %.8f, expected %.8f" % (p, r, values[0], want))
        if p > 0 and not values[1] > values[0]:
            failures.append("fog slab (%.2f, %.2f): more steps bring no scattered light (%.8f vs %.8f)"
                            % (p, r, values[1], values[0]))


def check_mc_slope(qrm, work, failures):
    xs, ys = [], []
    for n in (8, 32, 128, 512):
        s = run(qrm, ["--scene", "cornell_fog", "--method", "exact,mc", "--paths", str(n), "--seed", "3"],
                os.path.join(work, "mc%d" % n))
        xs.append(math.log(n))
        ys.append(math.log(s["rmse_vs_exact"]["mc"]))
        print("  %4d paths: RMSE %.5f (exact %.2f s, mc %.2f s)"
              % (n, s["rmse_vs_exact"]["mc"], s["seconds"]["exact"], s["seconds"]["mc"]))
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    print("cornell_fog 8^3: Monte Carlo RMSE vs exact over 8..512 paths: slope %.3f (N^-1/2: -0.5)" % slope)
    if not -0.6 <= slope <= -0.4:
        failures.append("Monte Carlo RMSE slope %.3f is not -0.5 +- 0.1" % slope)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    qrm, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = []
    t0 = time.time()
    check_beer_lambert(qrm, work, failures)
    check_mc_slope(qrm, work, failures)
    print("elapsed %.1f s" % (time.time() - t0))
    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        sys.exit(1)
    print("all media checks passed")


if __name__ == "__main__":
    main()
