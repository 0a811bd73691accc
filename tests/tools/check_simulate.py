#!/usr/bin/env python3
"""`qrm simulate`: its JSON, its --state-out file against an independent simulator, and its errors.

    check_simulate.py QRM WORKDIR

- A hand-written 6-qubit circuit (H, X, Ry, S, T, CX, CCX) run by a small state-vector simulator
  written here from the gates' textbook matrices (OpenQASM 3 stdgates, q[i] = bit i of the index):
  the file `--state-out` writes equals it for every scalar type the circuit allows, on the dense
  and the compact backend, fused and unfused. Tolerances: 1e-12 for double amplitudes (a few
  dozen roundings of numbers of size <= 1), 1e-5 for float (the same count at 2^-24 each).
- The file holds exactly 2^n amplitudes of the --scalar type (no header, no padding).
- A seeded random suite on 12 qubits: the compact and dense backends' states agree to 1e-12, and
  `--compare` (fused vs unfused on one backend) reports a difference <= 1e-12 with complex<double>.
- --chunk: the random suite applied in chunks of 1 KiB (runs of ops chunk by chunk) gives the
  op-by-op state (--chunk off) to 1e-12 (complex-double) / 1e-5 (complex-float), fused and not.
- --arithmetic float reaches the kernels: a complex-float state that differs from double
  arithmetic's, by at most 1e-5.
- The JSON has qubits, gates, fused_ops, seconds and norm (norm within 1e-9 of 1).
- Bad input: exit 2 and a message naming the flag and the value; no state file is left behind.
"""
import cmath
import json
import math
import os
import struct
import subprocess
import sys

N = 6
CIRCUIT = [
    ("h", [0]), ("ry", [1], 0.7), ("cx", [0, 2]), ("x", [3]), ("ccx", [0, 1, 4]), ("ry", [5], -1.3),
    ("cx", [5, 3]), ("h", [2]), ("s", [1]), ("t", [4]), ("ccx", [2, 3, 0]), ("ry", [0], 2.1),
    ("cx", [4, 5]), ("t", [0]), ("h", [5]), ("s", [3]), ("cx", [1, 0]), ("ry", [2], 0.4),
]
REAL = {"h", "x", "ry", "cx", "ccx"}


def qasm(circuit):
    lines = ["OPENQASM 3.0;", 'include "stdgates.inc";', "qubit[%d] q;" % N]
    for g in circuit:
        args = ", ".join("q[%d]" % i for i in g[1])
        lines.append("%s%s %s;" % (g[0], "(%r)" % g[2] if len(g) > 2 else "", args))
    return "\n".join(lines) + "\n"


def reference(circuit):
    """The state after `circuit` from |0...0>, by the definition of each gate."""
    s = [0j] * (1 << N)
    s[0] = 1
    r2 = 1 / math.sqrt(2)
    for g in circuit:
        name, q = g[0], g[1]
        if name in ("cx", "ccx"):
            controls, target = q[:-1], q[-1]
            for i in range(1 << N):
                if all(i >> c & 1 for c in controls) and not i >> target & 1:
                    j = i | 1 << target
                    s[i], s[j] = s[j], s[i]
            continue
        if name == "h":
            m = ((r2, r2), (r2, -r2))
        elif name == "x":
            m = ((0, 1), (1, 0))
        elif name == "ry":
            c, sn = math.cos(g[2] / 2), math.sin(g[2] / 2)
            m = ((c, -sn), (sn, c))
        elif name == "s":
            m = ((1, 0), (0, 1j))
        else:
            m = ((1, 0), (0, cmath.exp(1j * math.pi / 4)))
        t = q[0]
        for i in range(1 << N):
            if not i >> t & 1:
                j = i | 1 << t
                a, b = s[i], s[j]
                s[i], s[j] = m[0][0] * a + m[0][1] * b, m[1][0] * a + m[1][1] * b
    return s


SIZES = {"complex-double": ("d", 2), "complex-float": ("f", 2), "double": ("d", 1), "float": ("f", 1)}


def read_state(path, scalar):
    code, parts = SIZES[scalar]
    raw = open(path, "rb").read()
    width = struct.calcsize(code)
    count = len(raw) // (width * parts)
    if count * width * parts != len(raw):
        raise ValueError("%s: %d bytes is not a whole number of %s amplitudes" % (path, len(raw), scalar))
    values = struct.unpack("<%d%s" % (count * parts, code), raw)
    return [complex(values[2 * i], values[2 * i + 1]) for i in range(count)] if parts == 2 else [complex(v) for v in values]


def run(qrm, args, expect=0):
    r = subprocess.run([qrm, "simulate"] + args, capture_output=True, text=True)
    if r.returncode != expect:
        sys.exit("qrm simulate %s: exit %d (expected %d): %s%s" % (" ".join(args), r.returncode, expect, r.stdout, r.stderr))
    return r


def main():
    qrm, work = sys.argv[1:3]
    os.makedirs(work, exist_ok=True)
    failures = []
    for real in (True, False):
        circuit = [g for g in CIRCUIT if g[0] in REAL] if real else CIRCUIT
        path = os.path.join(work, "real.qasm" if real else "complex.qasm")
        open(path, "w").write(qasm(circuit))
        expected = reference(circuit)
        scalars = list(SIZES) if real else ["complex-double", "complex-float"]
        for scalar in scalars:
            tolerance = 1e-12 if "double" in scalar else 1e-5
            for backend in ("dense", "compact"):
                for fuse in ("off", "on", "3", "5"):
                    out = os.path.join(work, "state.bin")
                    if os.path.exists(out):
                        os.remove(out)
                    r = run(qrm, ["--qasm", path, "--scalar", scalar, "--backend", backend, "--fuse", fuse, "--threads", "1",
                                  "--repeat", "1", "--state-out", out])
                    j = json.loads(r.stdout)
                    what = "%s %s %s --fuse %s" % (os.path.basename(path), scalar, backend, fuse)
                    for key in ("qubits", "gates", "fused_ops", "seconds", "norm"):
                        if key not in j:
                            failures.append("%s: no '%s' in %s" % (what, key, r.stdout.strip()))
                    if j.get("qubits") != N or j.get("gates") != len(circuit):
                        failures.append("%s: qubits %s gates %s, expected %d and %d" % (what, j.get("qubits"), j.get("gates"), N, len(circuit)))
                    if abs(j.get("norm", 0) - 1) > 1e-9 if "double" in scalar else abs(j.get("norm", 0) - 1) > 1e-5:
                        failures.append("%s: norm %s" % (what, j.get("norm")))
                    try:
                        got = read_state(out, scalar)
                    except ValueError as e:
                        failures.append("%s: %s" % (what, e))
                        continue
                    if len(got) != 1 << N:
                        failures.append("%s: %d amplitudes, expected %d" % (what, len(got), 1 << N))
                        continue
                    worst = max(abs(a - b) for a, b in zip(got, expected))
                    if worst > tolerance:
                        failures.append("%s: state differs from the reference by %.3g (> %g)" % (what, worst, tolerance))

    # The random suite: compact and dense give the same state; --compare reports fused == unfused.
    states = {}
    for backend in ("dense", "compact"):
        out = os.path.join(work, "random_%s.bin" % backend)
        r = run(qrm, ["--random", "12", "--gates", "200", "--seed", "7", "--backend", backend, "--repeat", "1", "--compare",
                      "--state-out", out])
        j = json.loads(r.stdout)
        if not j["max_abs_difference"] <= 1e-12:
            failures.append("random suite, %s: fused and unfused differ by %g" % (backend, j["max_abs_difference"]))
        if j["fused_ops"] >= j["gates"]:
            failures.append("random suite, %s: fusion left %d ops of %d gates" % (backend, j["fused_ops"], j["gates"]))
        states[backend] = read_state(out, "complex-double")
    # --chunk 1 --chunk-passes 0: 64-128 amplitudes per chunk of a 12-qubit state, and every run
    # that fits is chunked (the default rule leaves cheap runs op by op).
    for scalar, tolerance in (("complex-double", 1e-12), ("complex-float", 1e-5)):
        for fuse in ("off", "3"):
            chunked = {}
            for chunk in ("off", "1"):
                out = os.path.join(work, "chunk_%s.bin" % chunk)
                passes = ["--chunk-passes", "0"] if chunk != "off" else []
                r = run(qrm, ["--random", "12", "--gates", "200", "--seed", "5", "--scalar", scalar, "--fuse", fuse,
                              "--chunk", chunk, "--threads", "2", "--repeat", "1", "--state-out", out] + passes)
                reported = json.loads(r.stdout)
                if reported.get("chunk_kib") != (1 if chunk == "1" else "off"):
                    failures.append("--chunk %s: the JSON says chunk_kib %r" % (chunk, reported.get("chunk_kib")))
                if chunk != "off" and reported.get("chunk_min_passes") != 0:
                    failures.append("--chunk-passes 0: the JSON says chunk_min_passes %r" % reported.get("chunk_min_passes"))
                chunked[chunk] = read_state(out, scalar)
            worst = max(abs(a - b) for a, b in zip(chunked["off"], chunked["1"]))
            if worst > tolerance:
                failures.append("--chunk 1 against off, %s --fuse %s: states differ by %.3g" % (scalar, fuse, worst))
    # --fuse-scope: fused within the chunked runs (chunks of 1 KiB: 6 of 12 qubits) or across the
    # program, the same state, and the JSON says which.
    scoped = {}
    for scope in ("runs", "program"):
        out = os.path.join(work, "scope_%s.bin" % scope)
        r = run(qrm, ["--random", "12", "--gates", "200", "--seed", "9", "--fuse", "2", "--fuse-scope", scope, "--chunk",
                      "1", "--chunk-passes", "0", "--threads", "1", "--repeat", "1", "--state-out", out])
        reported = json.loads(r.stdout)
        if reported.get("fuse_scope") != scope or reported.get("fuse_run_qubits") != (6 if scope == "runs" else None):
            failures.append("--fuse-scope %s: the JSON says fuse_scope %r, fuse_run_qubits %r" %
                            (scope, reported.get("fuse_scope"), reported.get("fuse_run_qubits")))
        scoped[scope] = read_state(out, "complex-double")
    worst = max(abs(a - b) for a, b in zip(scoped["runs"], scoped["program"]))
    if worst > 1e-12:
        failures.append("--fuse-scope runs against program: states differ by %.3g" % worst)

    # --arithmetic float (complex<float>): computed differently from double arithmetic (the
    # flag reaches the kernels), within float rounding of it (1e-5, as above).
    floats = {}
    for arithmetic in ("double", "float"):
        out = os.path.join(work, "random_%s_arith.bin" % arithmetic)
        r = run(qrm, ["--random", "14", "--gates", "200", "--seed", "3", "--scalar", "complex-float", "--arithmetic",
                      arithmetic, "--threads", "1", "--repeat", "1", "--state-out", out])
        if json.loads(r.stdout).get("arithmetic") != arithmetic:
            failures.append("--arithmetic %s: the JSON says %s" % (arithmetic, r.stdout.strip()))
        floats[arithmetic] = read_state(out, "complex-float")
    worst = max(abs(a - b) for a, b in zip(floats["double"], floats["float"]))
    if not 0 < worst <= 1e-5:
        failures.append("--arithmetic float against double: largest difference %.3g (expected in (0, 1e-5])" % worst)
    worst = max(abs(a - b) for a, b in zip(states["dense"], states["compact"]))
    if len(states["dense"]) != 1 << 12 or worst > 1e-12:
        failures.append("random suite: dense and compact states differ by %.3g" % worst)

    # Bad input: exit 2, the flag and value named, no file written.
    real_qasm = os.path.join(work, "real.qasm")
    bad = [
        (["--random", "10", "--backend", "gpu"], "--backend must be dense or compact, got 'gpu'"),
        (["--random", "10", "--backend", "compact", "--threads", "2"], "--threads applies to --backend dense"),
        (["--random", "10", "--backend", "compact", "--simd", "avx2"], "--simd applies to --backend dense"),
        (["--random", "10", "--arithmetic", "half"], "--arithmetic must be double or float, got 'half'"),
        (["--random", "10", "--arithmetic", "float"], "--arithmetic float applies to --scalar complex-float on --backend dense"),
        (["--random", "10", "--fuse", "9"], "--fuse must be a width 1..6, auto, on or off, got '9'"),
        (["--random", "10", "--fuse-scope", "all"], "--fuse-scope must be auto, runs or program, got 'all'"),
        (["--random", "10", "--fuse", "off", "--fuse-scope", "runs"], "--fuse-scope applies to fusion; --fuse is off"),
        (["--random", "10", "--chunk", "off", "--fuse-scope", "runs"],
         "--fuse-scope applies to the dense backend with chunks (--chunk KIB)"),
        (["--random", "10", "--backend", "compact", "--fuse-scope", "program"],
         "--fuse-scope applies to the dense backend with chunks (--chunk KIB)"),
        (["--random", "10", "--chunk", "0"], "--chunk must be a size in KiB from 1 to 1048576, or off, got '0'"),
        (["--random", "10", "--chunk", "1M"], "--chunk must be a size in KiB from 1 to 1048576, or off, got '1M'"),
        (["--random", "10", "--backend", "compact", "--chunk", "64"], "--chunk applies to --backend dense"),
        (["--random", "10", "--chunk-passes", "2000"], "--chunk-passes must be a number of passes from 0 to 1000, got '2000'"),
        (["--random", "10", "--chunk-passes", "nan"], "--chunk-passes needs a finite number, got 'nan'"),
        (["--random", "10", "--chunk", "off", "--chunk-passes", "2"], "--chunk-passes needs chunks; it does nothing with --chunk off"),
        (["--random", "10", "--backend", "compact", "--chunk-passes", "2"], "--chunk-passes applies to --backend dense"),
        (["--random", "10", "--state-out", ""], "--state-out needs a value"),
        (["--random", "35", "--backend", "compact", "--state-out", os.path.join(work, "big.bin")],
         "--state-out writes all 2^35 amplitudes; it is limited to 34 qubits"),
        (["--qasm", os.path.join(work, "complex.qasm"), "--scalar", "float", "--state-out", os.path.join(work, "f.bin")],
         "stores real amplitudes"),
        (["--qasm", real_qasm, "--random", "4"], "give exactly one of --qasm FILE and --random N"),
    ]
    for args, message in bad:
        r = subprocess.run([qrm, "simulate"] + args, capture_output=True, text=True)
        if r.returncode != 2 or message not in r.stderr:
            failures.append("qrm simulate %s: exit %d, stderr %r (expected 2 and %r)" % (" ".join(args), r.returncode, r.stderr.strip(), message))
    for leftover in ("big.bin", "f.bin"):
        if os.path.exists(os.path.join(work, leftover)):
            failures.append("a refused run left %s behind" % leftover)
    # A directory that cannot be made (its parent is a file): exit 1 naming the path.
    under_file = os.path.join(real_qasm, "s.bin")
    r = subprocess.run([qrm, "simulate", "--random", "4", "--state-out", under_file], capture_output=True, text=True)
    if r.returncode != 1 or under_file not in r.stderr:
        failures.append("--state-out %s: exit %d, stderr %r" % (under_file, r.returncode, r.stderr.strip()))

    if failures:
        print("\n".join(failures))
        sys.exit(1)
    print("qrm simulate: states equal the reference simulator for every scalar and backend; JSON and errors as expected")


main()
