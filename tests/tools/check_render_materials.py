#!/usr/bin/env python3
"""Mirrors and glossy surfaces through the qrm tool, at the CLI's default size.

    check_render_materials.py QRM WORKDIR [VOXELS]

The scenes are cornell_mirror (the Cornell box with the tall block replaced by a mirror sphere,
radius 110 mm on the floor at x = 385, z = 330 mm, reflectance 0.9) and cornell_glossy (the same
sphere glossy, lobe 2), at the CLI's default size (32^3 for these two; VOXELS^3 if given) and
image size, 128x128.

1. The mirror reflects the red wall. Which pixels should show it is worked out here from the
   analytic scene alone (the published camera, the true sphere, the red wall plane x = 550 mm),
   not from the renderer: pixels whose ray meets the sphere away from its rim and whose mirror
   ray, r = d - 2 (d.n) n, meets the red wall far enough from its edges that the walk's
   discretisation (the reflected direction snapped to one of 64 directions, about 15 degrees
   apart at worst; voxel normals) still lands on the wall. The mean colour of those pixels in the
   exact image must match the mean colour of the red wall seen directly, over the same patch of
   wall, within 10% in R/G and in normalised red r / (r + g + b).
2. Monte Carlo converges to the exact image on both scenes: the least-squares slope of log RMSE
   over log N for N = 8, 32, 128, 512 paths per pixel lies in [-0.6, -0.4] (N^-1/2).
"""
import math
import os
import sys
import time

from render_check import check_mc_slope, read_pfm_pixels as read_pfm, run


# The analytic scene in millimetres (render/voxelize.hpp: cornell_box, cornell_mirror,
# box_scene_camera): camera at (278, 273, -800) looking along +z, +y up, right = forward x up =
# -x, vertical field of view 2 atan(12.5 / 35).
EYE = (278.0, 273.0, -800.0)
SPHERE, RADIUS = (385.0, 110.0, 330.0), 110.0
RED_X = 550.0


def camera_ray(px, py, w, h):
    half_h = 12.5 / 35.0
    half_w = half_h * w / h
    sx = ((px + 0.5) / w * 2 - 1) * half_w
    sy = (1 - (py + 0.5) / h * 2) * half_h
    d = (-sx, sy, 1.0)
    n = math.sqrt(sum(c * c for c in d))
    return tuple(c / n for c in d)


def hit_sphere(o, d):
    oc = [o[i] - SPHERE[i] for i in range(3)]
    b = sum(oc[i] * d[i] for i in range(3))
    c = sum(x * x for x in oc) - RADIUS * RADIUS
    disc = b * b - c
    if disc <= 0:
        return None
    t = -b - math.sqrt(disc)
    return t if t > 0 else None


def hit_red_wall(o, d):
    if d[0] <= 1e-9:
        return None
    t = (RED_X - o[0]) / d[0]
    p = [o[i] + t * d[i] for i in range(3)]
    return t, p


def regions(w, h):
    """Pixels of the mirror that show the red wall (with the wall points they show), and pixels
    of the red wall seen directly (with their points)."""
    slack = math.tan(math.radians(25))  # snapped direction and voxel normal: within 25 degrees
    mirror, wall = [], []
    for py in range(h):
        for px in range(w):
            d = camera_ray(px, py, w, h)
            t = hit_sphere(EYE, d)
            if t is not None:
                p = [EYE[i] + t * d[i] for i in range(3)]
                n = [(p[i] - SPHERE[i]) / RADIUS for i in range(3)]
                cos_in = -sum(d[i] * n[i] for i in range(3))
                if cos_in < 0.35:  # near the rim, where the voxelized sphere's outline is ragged
                    continue
                k = 2 * sum(d[i] * n[i] for i in range(3))
                r = [d[i] - k * n[i] for i in range(3)]
                hit = hit_red_wall(p, r)
                if hit is None:
                    continue
                tr, q = hit
                margin = max(60.0, slack * tr)
                if margin <= q[1] <= 550 - margin and margin <= q[2] <= 550 - margin:
                    mirror.append((px, py, q))
                continue
            hit = hit_red_wall(EYE, d)
            if hit is not None:
                _, q = hit
                if 30 <= q[1] <= 520 and 30 <= q[2] <= 520:
                    wall.append((px, py, q))
    return mirror, wall


def mean_colour(img, pixels):
    s = [0.0, 0.0, 0.0]
    for px, py, _ in pixels:
        c = img(px, py)
        for i in range(3):
            s[i] += c[i]
    return [x / len(pixels) for x in s]


def check_reflection(qrm, work, size_args, failures):
    out = os.path.join(work, "mirror")
    t0 = time.time()
    s = run(qrm, ["--scene", "cornell_mirror", *size_args, "--method", "exact", "--seed", "1"], out)
    voxels = s["settings"]["size"]
    name = "cornell_mirror_%d_exact.pfm" % voxels
    w, h, img = read_pfm(os.path.join(out, name))
    mirror, wall = regions(w, h)
    if len(mirror) < 20:
        failures.append("only %d pixels of the mirror show the red wall (the geometry of this check is off)" % len(mirror))
        return
    # The patch of red wall the mirror shows, and the direct view of the same patch.
    ys = [q[1] for _, _, q in mirror]
    zs = [q[2] for _, _, q in mirror]
    patch = [p for p in wall if min(ys) <= p[2][1] <= max(ys) and min(zs) <= p[2][2] <= max(zs)]
    if len(patch) < 20:
        failures.append("only %d directly seen red-wall pixels in the reflected patch" % len(patch))
        return
    m, d = mean_colour(img, mirror), mean_colour(img, patch)
    rg_m, rg_d = m[0] / m[1], d[0] / d[1]
    nr_m, nr_d = m[0] / sum(m), d[0] / sum(d)
    print("cornell_mirror %d^3 %dx%d exact (%.1f s): %d mirror pixels show the red wall, mean rgb (%.4f, %.4f, %.4f); "
          "the wall seen directly (%d pixels): (%.4f, %.4f, %.4f); R/G %.3f vs %.3f (%.1f%%), r/(r+g+b) %.3f vs %.3f (%.1f%%)"
          % (voxels, w, h, s["seconds"]["exact"], len(mirror), m[0], m[1], m[2], len(patch), d[0], d[1], d[2],
             rg_m, rg_d, 100 * abs(rg_m / rg_d - 1), nr_m, nr_d, 100 * abs(nr_m / nr_d - 1)))
    if not abs(rg_m / rg_d - 1) <= 0.10:
        failures.append("the mirror's R/G %.3f is not within 10%% of the red wall's %.3f" % (rg_m, rg_d))
    if not abs(nr_m / nr_d - 1) <= 0.10:
        failures.append("the mirror's normalised red %.3f is not within 10%% of the red wall's %.3f" % (nr_m, nr_d))
    print("elapsed %.1f s" % (time.time() - t0))


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    qrm, work = sys.argv[1], sys.argv[2]
    size_args = ["--voxels", sys.argv[3]] if len(sys.argv) == 4 else []
    size = sys.argv[3] + "^3" if size_args else "default size"
    os.makedirs(work, exist_ok=True)
    failures = []
    check_reflection(qrm, work, size_args, failures)
    for scene in ("cornell_mirror", "cornell_glossy"):
        check_mc_slope(qrm, os.path.join(work, scene), "%s, %s" % (scene, size), ["--scene", scene, *size_args],
                       failures)
    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        sys.exit(1)
    print("all material checks passed")


if __name__ == "__main__":
    main()
