#!/usr/bin/env python3
"""A 3D scene file's camera block: the renderer looks through it.

    check_scene_camera.py QRM SCENES_DIR WORKDIR

examples/scenes/room3d_8_corner.txt is room3d_8.txt (same voxel lines, checked here) plus a
camera block. Both are rendered with the exact path sum and Monte Carlo (same size, paths and
seed). The two exact images must differ (a different viewpoint), both must show the room (over
20% of the pixels lit), and in both views Monte Carlo must agree with the exact image as
statistics says it should: the mean over pixels of (mc - exact) within 4 standard errors
(from the per-pixel standard errors the renderer writes), per channel.
"""
import json
import math
import os
import shutil
import struct
import subprocess
import sys


def read_pfm(path):
    data = open(path, "rb").read()
    header, rest = data.split(b"\n", 1)
    if header != b"PF":
        sys.exit("%s: not a colour PFM" % path)
    dims, rest = rest.split(b"\n", 1)
    scale, rest = rest.split(b"\n", 1)
    w, h = map(int, dims.split())
    endian = "<" if float(scale) < 0 else ">"
    values = struct.unpack(endian + "%df" % (w * h * 3), rest[: w * h * 12])
    return w, h, values


def voxel_lines(path):
    lines = []
    for line in open(path):
        line = line.split("#", 1)[0].strip()
        if line and not line.startswith(("name ", "camera ")):
            lines.append(line)
    return lines


def main():
    qrm, scenes, work = sys.argv[1:4]
    failures = []
    plain, corner = os.path.join(scenes, "room3d_8.txt"), os.path.join(scenes, "room3d_8_corner.txt")
    if voxel_lines(plain) != voxel_lines(corner):
        failures.append("room3d_8_corner.txt is not room3d_8.txt plus a camera block")
    exact = {}
    for name, path in (("room3d_8", plain), ("room3d_8_corner", corner)):
        out = os.path.join(work, name)
        shutil.rmtree(out, ignore_errors=True)
        r = subprocess.run([qrm, "render", "--scene", path, "--method", "exact,mc", "--width", "48", "--height", "48",
                            "--paths", "64", "--quiet", "--out", out], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True, timeout=300)
        if r.returncode != 0:
            sys.exit("qrm render --scene %s failed: %s" % (path, r.stderr))
        json.loads(r.stdout)  # the summary is valid JSON
        w, h, ex = read_pfm(os.path.join(out, name + "_exact.pfm"))
        _, _, mc = read_pfm(os.path.join(out, name + "_mc.pfm"))
        _, _, se = read_pfm(os.path.join(out, name + "_mc_standard_error.pfm"))
        n = w * h
        lit = sum(1 for p in range(n) if max(ex[3 * p: 3 * p + 3]) > 0) / n
        if lit < 0.2:
            failures.append("%s: only %.0f%% of the pixels are lit" % (name, 100 * lit))
        for c in range(3):
            diff = sum(mc[3 * p + c] - ex[3 * p + c] for p in range(n)) / n
            err = math.sqrt(sum(se[3 * p + c] ** 2 for p in range(n))) / n
            if abs(diff) > 4 * err + 1e-12:
                failures.append("%s channel %d: mean(mc - exact) = %.3g, more than 4 standard errors (%.3g)"
                                % (name, c, diff, err))
        exact[name] = ex
    a, b = exact["room3d_8"], exact["room3d_8_corner"]
    mean_abs = sum(abs(x - y) for x, y in zip(a, b)) / len(a)
    scale = sum(a) / len(a)
    if not mean_abs > 0.05 * scale:
        failures.append("the camera block changed nothing: mean |difference| %.3g against mean radiance %.3g"
                        % (mean_abs, scale))
    if failures:
        print("\n".join(failures))
        sys.exit(1)
    print("the camera block is used (mean |difference| %.3g, mean radiance %.3g); mc agrees with exact in both views"
          % (mean_abs, scale))


if __name__ == "__main__":
    main()
