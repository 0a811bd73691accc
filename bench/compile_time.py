#!/usr/bin/env python3
"""What including qrm costs, against the standard headers alone, measured in one run.

    python3 bench/compile_time.py [--compilers g++,clang++] [--repeat 5]

Each translation unit is compiled `repeat` times, interleaved with its standard-headers-only
twin, and the best wall time of each is kept, so the ratios hold even when the machine's speed
drifts during the run (2-core VMs of one type measured 1.7x-4x apart). The twin of a unit
includes exactly the standard headers that the qrm headers it reaches include (read from the
compiler's dependency list), nothing else.

Units: the umbrella <qrm/qrm.hpp> with an empty main; the README tour's typed circuit through
only the headers it needs (circuit/compose, backends/dense, backends/measure), header-only and
with QRM_COMPILED_BACKENDS (the backends compiled once elsewhere in the program: the unit
<qrm/backends/compiled_backends.hpp>, also timed, is that once); and examples/typed_walk.cpp at
-O3 (time and peak memory), header-only and with the six QRM_COMPILED_ macros, as qrm's own build
compiles it (every layer's builders compiled once elsewhere: <qrm/walk/compiled_walk.hpp>, the
walk's, is also timed).

g++ collects garbage once its front end holds more than --param ggc-min-heapsize (128 MiB on
a machine with this much memory): a unit just above that line pays one collection (~0.3 s for
the umbrella). The table reports each unit's heap at that point, so a reader sees the margin.
"""
import argparse
import datetime
import os
import platform
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INCLUDE = os.path.join(ROOT, "include")

UMBRELLA = "#include <qrm/qrm.hpp>\nint main() {}\n"


def tour_circuit():
    """The first part of examples/tour.cpp (the typed circuit), through the layer headers it needs."""
    lines = open(os.path.join(ROOT, "examples", "tour.cpp")).read().splitlines()
    out = []
    for line in lines:
        if line.strip() == "#include <qrm/qrm.hpp>":
            out += ["#include <qrm/circuit/compose.hpp>", "#include <qrm/backends/dense.hpp>",
                    "#include <qrm/backends/measure.hpp>"]
            continue
        if "The paper's circuit for one start point" in line:
            break
        out.append(line)
    return "\n".join(out) + '\n  std::printf("%g\\n", p);\n}\n'


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit("compile_time.py: command failed: " + " ".join(cmd) + "\n" + r.stderr[-2000:])
    return r.stdout


def std_twin(compiler, source, flags):
    """The standard headers that the qrm headers reached from `source` include directly."""
    deps = run([compiler, "-std=c++20", "-I" + INCLUDE, "-M", source] + flags)
    headers = set()
    for path in re.split(r"[\s\\]+", deps):
        if "/qrm/" in path and path.endswith(".hpp") and os.path.exists(path):
            headers |= set(re.findall(r"^\s*#\s*include\s*<([a-z_]+)>", open(path).read(), re.M))
    headers |= set(re.findall(r"^\s*#\s*include\s*<([a-z_]+)>", open(source).read(), re.M))  # the unit's own
    return "".join(f"#include <{h}>\n" for h in sorted(headers)) + "int main() {}\n", len(headers)


def compile_once(compiler, source, flags):
    t0 = time.perf_counter()
    run([compiler, "-std=c++20", "-I" + INCLUDE, "-c", source, "-o", os.devnull] + flags)
    return time.perf_counter() - t0


def gc_heap_kib(source, flags):
    """g++'s front-end heap at its first collection point: the smallest ggc-min-heapsize (KiB)
    for which g++ does not collect, found by bisection."""
    lo, hi = 16384, 1048576
    while hi - lo > 512:
        mid = (lo + hi) // 2
        r = subprocess.run(["g++", "-std=c++20", "-I" + INCLUDE, "-c", source, "-o", os.devnull, "-ftime-report",
                            f"--param=ggc-min-heapsize={mid}"] + flags, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
        if "garbage collection" in r.stderr:
            lo = mid
        else:
            hi = mid
    return hi


def version(compiler):
    return run([compiler, "--version"]).splitlines()[0]


def cpu_model():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--compilers", default="g++,clang++")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--no-typed-walk", action="store_true", help="skip the -O3 typed_walk.cpp unit")
    args = ap.parse_args()

    tmp = tempfile.mkdtemp(prefix="qrm-compile-time-")
    separate = ["-DQRM_COMPILED_BACKENDS"]
    # As qrm's own build compiles examples/typed_walk.cpp: every layer's builders compiled once.
    separate_all = ["-DQRM_COMPILED_" + layer for layer in ("BACKENDS", "CIRCUIT", "ESTIMATION", "WALK", "RENDER", "IO")]
    units = {"umbrella": (UMBRELLA, []), "tour_circuit": (tour_circuit(), []),
             "tour_circuit, QRM_COMPILED_BACKENDS": (tour_circuit(), separate),
             "compiled_backends.hpp": ("#include <qrm/backends/compiled_backends.hpp>\n", []),
             "compiled_walk.hpp": ("#include <qrm/walk/compiled_walk.hpp>\n", [])}
    paths = {}
    for name, (text, _) in units.items():
        paths[name] = os.path.join(tmp, re.sub(r"\W+", "_", name) + ".cpp")
        open(paths[name], "w").write(text)

    print(f"# Compile time, {datetime.date.today()}, {cpu_model()}, {os.cpu_count()} cores, load "
          f"{os.getloadavg()[0]:.2f}; best of {args.repeat}, wall time\n")
    print("| compiler | unit | qrm | standard headers alone | ratio | g++ heap at first GC point |")
    print("|---|---|---|---|---|---|")
    for compiler in args.compilers.split(","):
        for name, path in paths.items():
            flags = units[name][1]
            twin_text, n = std_twin(compiler, path, flags)
            twin = path[:-4] + "_std.cpp"
            open(twin, "w").write(twin_text)
            best_q = best_s = float("inf")
            for _ in range(args.repeat):
                best_q = min(best_q, compile_once(compiler, path, flags))
                best_s = min(best_s, compile_once(compiler, twin, []))
            # The once-files' heap does not matter: no other unit pays for it.
            heap = (f"{gc_heap_kib(path, flags) / 1024:.1f} MiB (line: 128 MiB)"
                    if compiler == "g++" and not name.startswith("compiled_") else "")
            print(f"| {version(compiler)} | {name} (-O0) | {best_q:.2f} s | {best_s:.2f} s ({n} headers) | "
                  f"**{best_q / best_s:.2f}x** | {heap} |")
        for flags in ([], separate_all) if not args.no_typed_walk else ():
            src = os.path.join(ROOT, "examples", "typed_walk.cpp")
            best, peak = float("inf"), 0.0
            for _ in range(max(1, args.repeat // 2)):
                r = subprocess.run(["/usr/bin/time", "-f", "%e %M", compiler, "-std=c++20", "-O3", "-DNDEBUG",
                                    "-I" + INCLUDE, "-c", src, "-o", os.devnull] + flags,
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                if r.returncode != 0:
                    sys.exit("compile_time.py: typed_walk.cpp failed to compile:\n" + r.stderr[-2000:])
                secs, kib = r.stderr.strip().splitlines()[-1].split()
                best, peak = min(best, float(secs)), max(peak, int(kib) / 1024)
            how = ", the six QRM_COMPILED_ macros" if flags else ""
            print(f"| {version(compiler)} | examples/typed_walk.cpp (-O3{how}) | {best:.2f} s, {peak:.0f} MiB | | | |")


if __name__ == "__main__":
    main()
