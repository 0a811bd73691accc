#!/usr/bin/env python3
"""Every scene file under examples/scenes/ loads and renders, and the paper's scenes written out
there are the built-in ones.

    check_example_scenes.py QRM SCENES_DIR WORKDIR

- Every *.txt renders (2D: the light map with the default FAE; 3D: a 24x24 exact + Monte Carlo
  image), exits 0 and writes its summary.
- paper_4x4.txt, paper_8x8.txt and cornell_box_8.txt, rendered with the same flags as the
  built-in --scene paper_4x4, paper_8x8 and cornell --voxels 8, give byte-identical outputs (every
  file but the summary, whose timings differ; its other fields must match too). The files were
  written by hand (2D: the authors' tables) or by format_scene (the Cornell box), so this checks
  the parser, the writer and the built-in scenes against each other through the whole renderer.
- Every 2D scene is walked the same way by `qrm lightmap --exact` and by `qrm render` (the same
  default march: the file's `march` line, else the surface march): the light map's faithful
  column equals the render's exact column to 1e-12 on every cell and channel.
"""
import csv
import json
import os
import shutil
import subprocess
import sys

SMALL_3D = ["--width", "24", "--height", "24", "--method", "exact,mc", "--paths", "4"]
BUILTIN = {
    "paper_4x4.txt": ["--scene", "paper_4x4"],
    "paper_8x8.txt": ["--scene", "paper_8x8"],
    "cornell_box_8.txt": ["--scene", "cornell", "--voxels", "8"],
}


def scene_dims(path):
    for line in open(path):
        words = line.split("#", 1)[0].split()
        if len(words) == 2 and words[0] == "dims":
            return int(words[1])
    sys.exit("%s: no dims line" % path)


def render(qrm, args, out):
    shutil.rmtree(out, ignore_errors=True)
    r = subprocess.run([qrm, "render", *args, "--out", out, "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("qrm render %s failed (%d):\n%s" % (" ".join(args), r.returncode, r.stderr))
    return sorted(os.listdir(out))


def summary_without_times(path):
    s = json.load(open(path))
    s.pop("seconds", None)
    s.get("settings", {}).pop("threads", None)
    return s


def compare_lightmap(qrm, path, out, written, failures):
    """qrm lightmap's exact faithful map of `path` against the exact column of qrm render's."""
    r = subprocess.run([qrm, "lightmap", "--scene", path, "--exact", "--format", "csv"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("qrm lightmap --scene %s failed (%d):\n%s" % (path, r.returncode, r.stderr))
    rendered = [w for w in written if w.endswith("_lightmap.csv")]
    if len(rendered) != 1:
        failures.append("%s: qrm render wrote %d light map CSVs" % (path, len(rendered)))
        return
    exact = {(row["x"], row["y"], row["channel"]): float(row["exact"])
             for row in csv.DictReader(open(os.path.join(out, rendered[0])))}
    rows = list(csv.DictReader(r.stdout.splitlines()))
    worst = max(abs(float(row["faithful"]) - exact[(row["x"], row["y"], row["channel"])]) for row in rows)
    if len(rows) != len(exact) or not worst <= 1e-12:
        failures.append("%s: qrm lightmap and qrm render differ (%d vs %d cells, largest gap %.3g)"
                        % (path, len(rows), len(exact), worst))
    else:
        print("%s: qrm lightmap = qrm render's exact map (%d cell-channels, largest gap %.1e)" % (path, len(rows), worst))


def main():
    qrm, scenes, work = sys.argv[1:4]
    work = os.path.join(work, "example_scenes")
    files = sorted(f for f in os.listdir(scenes) if f.endswith(".txt"))
    missing = [f for f in BUILTIN if f not in files]
    if missing:
        sys.exit("examples/scenes/ lacks %s" % ", ".join(missing))
    failures = []
    for f in files:
        path = os.path.join(scenes, f)
        extra = SMALL_3D if scene_dims(path) == 3 else []
        out = os.path.join(work, f[:-4])
        written = render(qrm, ["--scene", path, *extra], out)
        if not any(w.endswith("_summary.json") for w in written):
            failures.append("%s: no summary written (%s)" % (f, written))
        print("%s: rendered, %d files" % (f, len(written)))
        if scene_dims(path) == 2:
            compare_lightmap(qrm, path, out, written, failures)
        if f not in BUILTIN:
            continue
        ref_out = out + "_builtin"
        ref_written = render(qrm, BUILTIN[f] + extra, ref_out)
        if written != ref_written:
            failures.append("%s: writes %s, the built-in scene %s" % (f, written, ref_written))
            continue
        for name in written:
            a, b = os.path.join(out, name), os.path.join(ref_out, name)
            if name.endswith("_summary.json"):
                same = summary_without_times(a) == summary_without_times(b)
            else:
                same = open(a, "rb").read() == open(b, "rb").read()
            if not same:
                failures.append("%s: %s differs from the built-in scene's" % (f, name))
        print("%s: identical to %s" % (f, " ".join(BUILTIN[f])))
    if failures:
        sys.exit("\n".join(failures))
    print("all %d example scenes render; the paper's scenes written out are the built-in ones" % len(files))


if __name__ == "__main__":
    main()
