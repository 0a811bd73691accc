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
import os
import sys
import time

from render_check import check_mc_slope, read_pfm_pixels as read_pfm, run






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




def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    qrm, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = []
    t0 = time.time()
    check_beer_lambert(qrm, work, failures)
    check_mc_slope(qrm, work, "cornell_fog 8^3", ["--scene", "cornell_fog"], failures)
    print("elapsed %.1f s" % (time.time() - t0))
    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        sys.exit(1)
    print("all media checks passed")


if __name__ == "__main__":
    main()
