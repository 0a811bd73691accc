#!/usr/bin/env python3
"""Progress on stderr follows the flags: a bar on a terminal, nothing in a log unless asked.

    check_cli_progress.py QRM WORKDIR

- stderr is a terminal (a pseudo-terminal here): `qrm render` draws its bar ("light map ... [#")
  and ends it with a newline; with --quiet, nothing.
- stderr is a pipe: nothing, without or with --quiet (a short job: --progress would print a line
  only every 10 s, so it is not observable here; its parsing is checked below).
- --quiet --progress together: exit 2 naming both.
"""
import os
import pty
import shutil
import subprocess
import sys

RENDER = ["render", "--scene", "paper_4x4", "--steps", "2"]


def on_terminal(qrm, args, out):
    """Runs qrm with stderr (and stdout) on a pseudo-terminal; returns (exit code, what it showed)."""
    shutil.rmtree(out, ignore_errors=True)
    pid, fd = pty.fork()
    if pid == 0:
        os.execv(qrm, [qrm, *args, "--out", out])
    shown = b""
    while True:
        try:
            chunk = os.read(fd, 4096)
        except OSError:  # EIO: the child closed the terminal
            break
        if not chunk:
            break
        shown += chunk
    _, status = os.waitpid(pid, 0)
    os.close(fd)
    return os.waitstatus_to_exitcode(status), shown.decode(errors="replace")


def main():
    qrm, work = os.path.abspath(sys.argv[1]), os.path.join(sys.argv[2], "cli_progress")
    os.makedirs(work, exist_ok=True)
    failures = []

    code, shown = on_terminal(qrm, RENDER, os.path.join(work, "tty"))
    if code != 0 or "light map paper_4x4 [#" not in shown or "100.0%" not in shown:
        failures.append("on a terminal: exit %d, no progress bar in %r" % (code, shown[-300:]))
    code, shown = on_terminal(qrm, RENDER + ["--quiet"], os.path.join(work, "tty_quiet"))
    if code != 0 or "light map paper_4x4 [" in shown:
        failures.append("on a terminal with --quiet: exit %d, showed %r" % (code, shown[-300:]))

    for extra in ([], ["--quiet"]):
        r = subprocess.run([qrm, *RENDER, *extra, "--out", os.path.join(work, "pipe")], capture_output=True, text=True)
        if r.returncode != 0 or r.stderr:
            failures.append("stderr a pipe %s: exit %d, stderr %r" % (extra, r.returncode, r.stderr))

    r = subprocess.run([qrm, *RENDER, "--quiet", "--progress", "--out", os.path.join(work, "both")],
                       capture_output=True, text=True)
    if r.returncode != 2 or "give either --quiet or --progress" not in r.stderr:
        failures.append("--quiet --progress: exit %d, stderr %r" % (r.returncode, r.stderr))

    if failures:
        sys.exit("\n".join(failures))
    print("progress: a bar on a terminal, silent in a pipe and with --quiet, as promised")


if __name__ == "__main__":
    main()
