#!/usr/bin/env python3
"""SIGTERM and SIGINT stop the qrm tool with exit 143 and 130 and leave no temporary file.

    check_cli_signals.py QRM WORKDIR

Starts a 3D render that takes several seconds, signals it after half a second, and checks the
exit code and that the output directory holds no ".tmp" file. (That a signal arriving in the
middle of a write removes the half-written file is tested deterministically in test_io.)
"""
import os
import shutil
import signal
import subprocess
import sys
import time


def main():
    qrm, work = sys.argv[1], sys.argv[2]
    failures = []
    for sig, code in ((signal.SIGTERM, 143), (signal.SIGINT, 130)):
        out = os.path.join(work, "signal_%d" % sig)
        shutil.rmtree(out, ignore_errors=True)
        p = subprocess.Popen([qrm, "render", "--scene", "cornell", "--method", "exact", "--width", "4096",
                              "--height", "4096", "--quiet", "--out", out],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        time.sleep(0.5)
        if p.poll() is not None:
            failures.append("the render ended before the signal (exit %s): %s" % (p.returncode, p.stderr.read()))
            continue
        p.send_signal(sig)
        try:
            p.wait(timeout=30)
        except subprocess.TimeoutExpired:
            p.kill()
            failures.append("signal %d did not stop the render within 30 s" % sig)
            continue
        if p.returncode != code:
            failures.append("signal %d: exit %s, expected %d" % (sig, p.returncode, code))
        left = [n for n in os.listdir(out) if n.endswith(".tmp")] if os.path.isdir(out) else []
        if left:
            failures.append("signal %d left temporary files: %s" % (sig, left))
    if failures:
        print("\n".join(failures))
        sys.exit(1)
    print("SIGTERM -> 143, SIGINT -> 130, no temporary files left")


if __name__ == "__main__":
    main()
