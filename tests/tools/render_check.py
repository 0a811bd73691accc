"""What the render checks (check_render_scale.py, check_render_materials.py,
check_render_media.py) share: running `qrm render`, reading its PFM images, and Monte Carlo's
convergence slope against the exact image."""
import array
import json
import math
import os
import shutil
import subprocess
import sys


def run(qrm, args, out):
    """qrm render ARGS --out OUT --quiet (OUT emptied first); the summary JSON it prints."""
    shutil.rmtree(out, ignore_errors=True)
    r = subprocess.run([qrm, "render", *args, "--out", out, "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("qrm render %s failed (%d):\n%s" % (" ".join(args), r.returncode, r.stderr))
    return json.loads(r.stdout)


def read_pfm(path):
    """(width, height, values): a colour PFM's float32 values, rows bottom to top as stored."""
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
    return w, h, a


def read_pfm_pixels(path):
    """(width, height, rgb(x, y)) with y = 0 the top row."""
    w, h, a = read_pfm(path)
    return w, h, lambda x, y: a[3 * ((h - 1 - y) * w + x):3 * ((h - 1 - y) * w + x) + 3]


def check_mc_slope(qrm, work, label, scene_args, failures, paths=(8, 32, 128, 512)):
    """Monte Carlo's RMSE against the exact image over `paths` per pixel must fall as N^-1/2: the
    least-squares slope of log RMSE over log N in [-0.6, -0.4]."""
    xs, ys = [], []
    for n in paths:
        s = run(qrm, [*scene_args, "--method", "exact,mc", "--paths", str(n), "--seed", "3"],
                os.path.join(work, "mc%d" % n))
        xs.append(math.log(n))
        ys.append(math.log(s["rmse_vs_exact"]["mc"]))
        print("  %4d paths: RMSE %.5f (exact %.2f s, mc %.2f s)"
              % (n, s["rmse_vs_exact"]["mc"], s["seconds"]["exact"], s["seconds"]["mc"]))
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    print("%s: Monte Carlo RMSE vs exact over %d..%d paths: slope %.3f (N^-1/2: -0.5)"
          % (label, paths[0], paths[-1], slope))
    if not -0.6 <= slope <= -0.4:
        failures.append("%s: Monte Carlo RMSE slope %.3f is not -0.5 +- 0.1" % (label, slope))
