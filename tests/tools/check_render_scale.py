#!/usr/bin/env python3
"""The bounce-driven (surface) walk at scale, through the qrm tool.

    check_render_scale.py QRM SCENES_DIR WORKDIR

1. The 64^3 Cornell box at 256x256, exact + Monte Carlo (64 paths), with the defaults (surface
   march): writes cornell_box_64_exact.pfm and cornell_box_64_mc.pfm; at least 90% of the exact
   image's pixels are lit (luminance > 1e-3); the left fifth of the image is red (mean R > 2 mean
   G: the red wall) and the right fifth green (mean G > 2 mean R). The seconds are printed (the
   time bar is a benchmark matter, not asserted here).
2. Monte Carlo's RMSE against the exact image falls as N^-1/2: the least-squares slope of
   log RMSE over log N for N = 8, 32, 128, 512 paths lies in [-0.6, -0.4].
3. The mirror-symmetric 2D room (examples/scenes/room2d_symmetric_8.txt: surface march,
   symmetric Lambertian coin) gives a light map symmetric under x -> 7 - x to 1e-12, for the
   exact faithful values and the classical path sum; every cell the light shines on directly
   (along one of the 8 walk directions) is lit; the same room with the paper's coin is not
   symmetric (so the check can fail).
4. --march voxel runs the paper's walk (summary: march voxel, 15 directions, 3 sub-voxel bits).
5. Black stays black: in a 16^3 render with exact, emulated and fully quantum images, every pixel
   channel whose exact value is 0 is exactly 0 in the emulated and the quantum image (no
   estimator floor), and the others are not all 0.
"""
import csv
import json
import math
import os
import subprocess
import sys

from render_check import check_mc_slope, read_pfm, run






def check_cornell(qrm, work, failures):
    out = os.path.join(work, "cornell64")
    s = run(qrm, ["--scene", "cornell", "--voxels", "64", "--width", "256", "--height", "256", "--method", "exact,mc",
                  "--paths", "64", "--seed", "1"], out)
    for f in ("cornell_box_64_exact.pfm", "cornell_box_64_mc.pfm"):
        if not os.path.exists(os.path.join(out, f)):
            failures.append("64^3 render did not write %s" % f)
            return
    if s["settings"].get("march") != "surface":
        failures.append("the 3D default march is %s, not surface" % s["settings"].get("march"))
    w, h, a = read_pfm(os.path.join(out, "cornell_box_64_exact.pfm"))
    lit = sum(1 for i in range(w * h) if 0.2126 * a[3 * i] + 0.7152 * a[3 * i + 1] + 0.0722 * a[3 * i + 2] > 1e-3)

    def mean(x0, x1):
        r = g = 0.0
        for y in range(h):
            for x in range(x0, x1):
                i = 3 * (y * w + x)
                r += a[i]
                g += a[i + 1]
        return r, g

    lr, lg = mean(0, w // 5)
    rr, rg = mean(w - w // 5, w)
    print("64^3 Cornell box 256x256: exact %.2f s, mc (64 paths) %.2f s; lit %.3f; left R/G %.2f; right G/R %.2f"
          % (s["seconds"]["exact"], s["seconds"]["mc"], lit / (w * h), lr / lg, rg / rr))
    if lit < 0.9 * w * h:
        failures.append("only %.3f of the exact image's pixels are lit (need 0.9)" % (lit / (w * h)))
    if not lr > 2 * lg:
        failures.append("the left fifth is not red: mean R %.4g, G %.4g" % (lr, lg))
    if not rg > 2 * rr:
        failures.append("the right fifth is not green: mean G %.4g, R %.4g" % (rg, rr))




def lightmap(qrm, scene, out):
    run(qrm, ["--scene", scene, "--seed", "1"], out)
    name = [f for f in os.listdir(out) if f.endswith("_lightmap.csv")]
    if len(name) != 1:
        sys.exit("%s: expected one light map CSV, found %s" % (out, name))
    cells = {}
    for row in csv.DictReader(open(os.path.join(out, name[0]))):
        cells[(int(row["x"]), int(row["y"]), int(row["channel"]))] = row
    return cells


def asymmetry(cells, column):
    worst = 0.0
    for (x, y, c), row in cells.items():
        v, m = float(row[column]), float(cells[(7 - x, y, c)][column])
        worst = max(worst, abs(v - m))
    return worst


def cells_seeing_light(path):
    """Air cells of a 2D scene file (its fill and voxel lines) from which one of the 8 king
    directions reaches an emitting cell first: the cells the light shines on directly."""
    kind, emits, colors = {}, set(), {}
    for line in open(path):
        w = line.split("#", 1)[0].split()
        if not w:
            continue
        if w[0] == "size":
            n = int(w[1])
        elif w[0] == "color":
            colors[w[1]] = [float(v) for v in w[2:5]]
        elif w[0] in ("fill", "voxel"):
            coords = [int(v) for v in w[1:5]] if w[0] == "fill" else [int(w[1]), int(w[2])] * 2
            x0, y0, x1, y1 = coords
            rest = w[5:] if w[0] == "fill" else w[3:]
            le = rest[rest.index("le") + 1] if "le" in rest else None
            for y in range(y0, y1 + 1):
                for x in range(x0, x1 + 1):
                    kind[(x, y)] = rest[0]
                    if le and any(v > 0 for v in colors[le]):
                        emits.add((x, y))
    seeing = []
    for y in range(n):
        for x in range(n):
            if (x, y) in kind:
                continue
            for dx, dy in ((0, -1), (1, -1), (1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1)):
                px, py = x + dx, y + dy
                while 0 <= px < n and 0 <= py < n and (px, py) not in kind:
                    px, py = px + dx, py + dy
                if (px, py) in emits:
                    seeing.append((x, y))
                    break
    return seeing


def check_symmetric_room(qrm, scenes, work, failures):
    path = os.path.join(scenes, "room2d_symmetric_8.txt")
    cells = lightmap(qrm, path, os.path.join(work, "sym"))
    for column in ("exact", "classical"):
        a = asymmetry(cells, column)
        print("symmetric room, %s light map: largest |v(x, y) - v(7 - x, y)| = %.3g" % (column, a))
        if a > 1e-12:
            failures.append("the symmetric room's %s light map is not symmetric: %.3g" % (column, a))
    seeing = cells_seeing_light(path)
    dark = [(x, y) for (x, y) in seeing if float(cells[(x, y, 0)]["classical"]) <= 0]
    lit = sum(1 for (x, y, c), row in cells.items() if c == 0 and float(row["classical"]) > 0)
    print("symmetric room: %d cells see the light along a walk direction, none of them black; %d of 64 cells lit"
          % (len(seeing), lit))
    if len(seeing) < 10 or dark:
        failures.append("cells that see the light are black: %s (of %d)" % (dark[:8], len(seeing)))
    text = open(path).read().replace("lambertian symmetric", "lambertian paper")
    paper = os.path.join(work, "room2d_paper_coin.txt")
    with open(paper, "w") as f:
        f.write(text)
    a = asymmetry(lightmap(qrm, paper, os.path.join(work, "paper_coin")), "classical")
    print("the same room with the paper's coin: asymmetry %.3g" % a)
    if a < 1e-3:
        failures.append("the paper's coin gave a symmetric map too (%.3g): the check cannot tell" % a)


def check_voxel_march(qrm, work, failures):
    s = run(qrm, ["--scene", "cornell", "--voxels", "8", "--width", "16", "--height", "16", "--method", "exact",
                  "--march", "voxel"], os.path.join(work, "voxel"))
    st = s["settings"]
    if (st["march"], st["directions"], st["fractional_bits"]) != ("voxel", 15, 3):
        failures.append("--march voxel settings: %s" % st)


def check_black_stays_black(qrm, work, failures):
    out = os.path.join(work, "black")
    run(qrm, ["--scene", "cornell", "--voxels", "16", "--width", "32", "--height", "32", "--method",
              "exact,emulated,quantum", "--paths", "16", "--seed", "2"], out)
    _, _, exact = read_pfm(os.path.join(out, "cornell_box_16_exact.pfm"))
    zeros = [i for i, v in enumerate(exact) if v == 0]
    for method in ("emulated", "quantum"):
        _, _, img = read_pfm(os.path.join(out, "cornell_box_16_%s.pfm" % method))
        bad = [i for i in zeros if img[i] != 0]
        lit = sum(1 for i, v in enumerate(exact) if v > 0 and img[i] > 0)
        print("black stays black, %s: %d of %d zero pixel-channels are 0 (%d lit ones lit)"
              % (method, len(zeros) - len(bad), len(zeros), lit))
        if bad or not zeros or lit == 0:
            failures.append("%s: %d of %d zero pixel-channels are not 0 (first values %s)"
                            % (method, len(bad), len(zeros), [img[i] for i in bad[:4]]))


def main():
    qrm, scenes, work = sys.argv[1:4]
    work = os.path.join(work, "render_scale")
    os.makedirs(work, exist_ok=True)
    failures = []
    check_cornell(qrm, work, failures)
    check_mc_slope(qrm, work, "cornell 64^3 at 64x64",
                   ["--scene", "cornell", "--voxels", "64", "--width", "64", "--height", "64"], failures)
    check_symmetric_room(qrm, scenes, work, failures)
    check_voxel_march(qrm, work, failures)
    check_black_stays_black(qrm, work, failures)
    if failures:
        sys.exit("\n".join(failures))
    print("render at scale: as promised")


if __name__ == "__main__":
    main()
