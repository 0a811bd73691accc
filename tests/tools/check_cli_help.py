#!/usr/bin/env python3
"""The qrm tool's help against what it parses.

    check_cli_help.py QRM SOURCE_DIR

- `qrm --help`, `qrm -h` and `qrm help` exit 0 and list the commands; `qrm --version` and
  `qrm version` print "qrm X.Y.Z".
- For every command C listed: `qrm C --help`, `qrm C -h` and `qrm help C` exit 0 with the same
  text, which has an example line starting "qrm C".
- Every flag C's help lists is accepted by C: `qrm C --FLAG v --zzz-not-a-flag` must fail on the
  made-up flag, not on --FLAG (flags are checked in sorted order, so the first unknown one is
  named). A made-up flag alone is refused.
- Every flag name the tool's sources read (a.str("x"), a.flag("x"), number_in("x"), ...) is
  listed by some command's help: a flag that is parsed but undocumented fails here.
"""
import os
import re
import subprocess
import sys


def run(qrm, *argv):
    r = subprocess.run([qrm, *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60)
    return r.returncode, r.stdout, r.stderr


def main():
    qrm, source_dir = sys.argv[1], sys.argv[2]
    failures = []

    def check(cond, what):
        if not cond:
            failures.append(what)

    rc, top, _ = run(qrm, "--help")
    check(rc == 0, "qrm --help: exit %d" % rc)
    for alias in (["-h"], ["help"]):
        rc2, out2, _ = run(qrm, *alias)
        check(rc2 == 0 and out2 == top, "qrm %s differs from qrm --help (exit %d)" % (alias[0], rc2))
    for argv in (["--version"], ["version"]):
        rc, out, _ = run(qrm, *argv)
        check(rc == 0 and re.fullmatch(r"qrm \d+\.\d+\.\d+\n", out) is not None,
              "qrm %s: exit %d, printed %r" % (argv[0], rc, out))
    commands = re.findall(r"^  ([a-z]+)\s{2,}", top.split("commands:", 1)[-1], re.M)
    check(len(commands) >= 8, "qrm --help lists %d commands: %s" % (len(commands), commands))

    documented = set()
    for c in commands:
        rc, text, err = run(qrm, c, "--help")
        check(rc == 0, "qrm %s --help: exit %d: %s" % (c, rc, err))
        for alias in ([c, "-h"], ["help", c]):
            rc2, text2, _ = run(qrm, *alias)
            check(rc2 == 0 and text2 == text, "qrm %s differs from qrm %s --help" % (" ".join(alias), c))
        check(re.search(r"^example:\n  qrm %s\b" % c, text, re.M) is not None, "qrm %s --help has no example" % c)
        flags = [f for f in re.findall(r"^  --([a-z][a-z0-9-]*)", text, re.M) if f != "help"]
        documented |= set(flags)
        for f in flags:
            rc, _, err = run(qrm, c, "--" + f, "1", "--zzz-not-a-flag", "1")
            check(rc == 2 and "unknown flag --zzz-not-a-flag" in err,
                  "qrm %s --%s: the flag its help lists is not accepted (exit %d): %s" % (c, f, rc, err.strip()))
        rc, _, err = run(qrm, c, "--zzz-not-a-flag")
        check(rc == 2 and "unknown flag --zzz-not-a-flag" in err, "qrm %s accepts a made-up flag: %s" % (c, err))

    read = set()
    pattern = re.compile(r"\b(?:a\.(?:str|flag|has|integer|number|required|required_number)|number_in|integer_in|word)"
                         r"\(\s*\"([a-z][a-z0-9-]*)\"")
    for name in os.listdir(source_dir):
        if name.endswith((".cpp", ".hpp")):
            read |= set(pattern.findall(open(os.path.join(source_dir, name)).read()))
    check(len(read) >= 20, "found only %d flag reads in %s: the pattern is stale" % (len(read), source_dir))
    for f in sorted(read - documented):
        failures.append("--%s is read by the tool's sources but no command's --help lists it" % f)

    if failures:
        print("\n".join(failures))
        sys.exit(1)
    print("%d commands, %d documented flags, all accepted; %d flags read, all documented"
          % (len(commands), len(documented), len(read)))


if __name__ == "__main__":
    main()
