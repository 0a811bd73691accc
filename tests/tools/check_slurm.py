#!/usr/bin/env python3
"""examples/slurm/render_array.sh on a real Slurm: a single-node cluster started for the test.

    check_slurm.py QRM RENDER_ARRAY_SH WORKDIR

Starts munged, slurmctld and slurmd (Debian's slurm-wlm and munge) on localhost with their
own key, ports, state and logs in a temporary directory, then:
  1. renders the Cornell box (exact, Monte Carlo, emulated) as a 3-task job array plus the
     dependent merge job, and checks the merged images are byte-identical to one `qrm render`
     with the same flags on this machine (and the summary's scene, RMSE and settings);
  2. submits an array whose tasks fail (an unknown scene) and checks the merge job is cancelled
     rather than left waiting;
  3. checks the script refuses --tile (it sets the tiling itself) before submitting anything.
Everything started is stopped at the end, also on failure. Exits 77 (ctest: skipped) with the
reason when Slurm or munge is not installed or this is not root (slurmd starts jobs as root).
"""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

SKIP = 77
FLAGS = ["--scene", "cornell", "--voxels", "8", "--width", "40", "--height", "24",
         "--method", "exact,mc,emulated", "--paths", "4", "--seed", "7", "--quiet"]
TOOLS = ["munged", "munge", "slurmctld", "slurmd", "sbatch", "sinfo", "scontrol"]


def skip(reason):
    print("SKIPPED: " + reason)
    sys.exit(SKIP)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cluster:
    def __init__(self, root):
        self.root = root
        self.procs = []
        self.env = dict(os.environ, SLURM_CONF=os.path.join(root, "slurm.conf"))

    def start(self):
        r = self.root
        os.chmod(r, 0o755)  # munge: every directory above its socket must be searchable by all
        for d in ("key", "run", "state", "spool", "log"):
            os.makedirs(os.path.join(r, d), mode=0o700 if d == "key" else 0o755)
        key = os.path.join(r, "key", "munge.key")
        with open(key, "wb") as f:
            f.write(os.urandom(1024))
        os.chmod(key, 0o400)
        sock = os.path.join(r, "run", "munge.sock")
        self.spawn("munged", ["munged", "-F", "--socket=" + sock, "--key-file=" + key,
                              "--pid-file=" + os.path.join(r, "run", "munged.pid"),
                              "--log-file=" + os.path.join(r, "log", "munged.log"),
                              "--seed-file=" + os.path.join(r, "key", "seed")])
        self.wait_for(lambda: os.path.exists(sock), "munged's socket", 20)
        conf = "\n".join([
            "ClusterName=qrmtest", "SlurmctldHost=localhost",
            "SlurmctldPort=%d" % free_port(), "SlurmdPort=%d" % free_port(),
            "SlurmUser=root", "SlurmdUser=root",
            "AuthType=auth/munge", "CredType=cred/munge", "AuthInfo=socket=" + sock,
            "StateSaveLocation=" + os.path.join(r, "state"), "SlurmdSpoolDir=" + os.path.join(r, "spool"),
            "SlurmctldPidFile=" + os.path.join(r, "run", "slurmctld.pid"),
            "SlurmdPidFile=" + os.path.join(r, "run", "slurmd.pid"),
            "SlurmctldLogFile=" + os.path.join(r, "log", "slurmctld.log"),
            "SlurmdLogFile=" + os.path.join(r, "log", "slurmd.log"),
            # No cgroups, accounting or MPI: a container or VM need not provide them.
            "ProctrackType=proctrack/linuxproc", "TaskPlugin=task/none",
            "JobAcctGatherType=jobacct_gather/none", "AccountingStorageType=accounting_storage/none",
            "SelectType=select/cons_tres", "SelectTypeParameters=CR_CPU", "MpiDefault=none",
            "ReturnToService=2", "MinJobAge=600",
            "NodeName=localhost CPUs=%d State=UNKNOWN" % os.cpu_count(),
            "PartitionName=qrm Nodes=localhost Default=YES MaxTime=INFINITE State=UP", ""])
        with open(self.env["SLURM_CONF"], "w") as f:
            f.write(conf)
        self.spawn("slurmctld", ["slurmctld", "-D"])
        self.spawn("slurmd", ["slurmd", "-D", "-N", "localhost"])
        self.wait_for(lambda: self.run(["sinfo", "-h", "-o", "%t"]).stdout.strip() == "idle", "an idle node", 60)

    def spawn(self, name, argv):
        log = open(os.path.join(self.root, "log", name + ".out"), "w")
        self.procs.append((name, subprocess.Popen(argv, env=self.env, stdout=log, stderr=subprocess.STDOUT)))

    def run(self, argv, **kw):
        return subprocess.run(argv, env=self.env, capture_output=True, text=True, **kw)

    def wait_for(self, ready, what, seconds):
        deadline = time.time() + seconds
        while time.time() < deadline:
            for name, p in self.procs:
                if p.poll() is not None:
                    self.fail("%s exited (%d) while waiting for %s" % (name, p.returncode, what))
            if ready():
                return
            time.sleep(0.5)
        self.fail("no %s after %d s" % (what, seconds))

    def job_state(self, job):
        r = self.run(["scontrol", "show", "job", job])
        for word in r.stdout.split():
            if word.startswith("JobState="):
                return word.split("=", 1)[1]
        return "UNKNOWN"

    def wait_job(self, job, seconds=180):
        final = ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY")
        state = []
        self.wait_for(lambda: state.append(self.job_state(job)) or state[-1] in final, "end of job " + job, seconds)
        return state[-1]

    def fail(self, message):
        for name in sorted(os.listdir(os.path.join(self.root, "log"))):
            with open(os.path.join(self.root, "log", name), errors="replace") as f:
                print("---- %s (last lines)\n%s" % (name, "".join(f.readlines()[-15:])))
        raise SystemExit("FAILED: " + message)

    def stop(self):
        for _, p in reversed(self.procs):
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for _, p in reversed(self.procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def submit(cluster, script, qrm, tiles, out, flags):
    r = subprocess.run(["bash", script, str(tiles), out, *flags], env=dict(cluster.env, QRM=qrm),
                       capture_output=True, text=True)
    if r.returncode != 0:
        cluster.fail("render_array.sh exited %d: %s" % (r.returncode, r.stderr))
    array_id, merge_id = r.stdout.split()
    return array_id, merge_id


def summary_results(path):
    """What a merged summary shares with a whole render's (not timings or the tile count)."""
    s = json.load(open(path))
    return {k: s.get(k) for k in ("scene", "kind", "rmse_vs_exact", "settings")}


def main():
    qrm, script, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2]), sys.argv[3]
    work = os.path.abspath(os.path.join(work, "slurm_job_array"))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    # 3. needs no cluster: the script refuses a flag it sets itself, and submits nothing.
    r = subprocess.run(["bash", script, "2", os.path.join(work, "refused"), "--scene", "cornell", "--tile", "0/2"],
                       env=dict(os.environ, QRM=qrm), capture_output=True, text=True)
    if r.returncode != 2 or "--tile" not in r.stderr or os.path.exists(os.path.join(work, "refused")):
        sys.exit("FAILED: render_array.sh with --tile: exit %d, stderr %r" % (r.returncode, r.stderr))

    missing = [t for t in TOOLS if shutil.which(t) is None]
    if missing:
        skip("not installed: %s (Debian: apt-get install slurm-wlm munge)" % " ".join(missing))
    if os.geteuid() != 0:
        skip("not root: slurmd must run as root to start jobs as the submitting user")

    # Short path: munge's socket path must fit in sockaddr_un (108 bytes).
    cluster = Cluster(tempfile.mkdtemp(prefix="qrm-slurm-"))
    try:
        t0 = time.time()
        cluster.start()
        print("single-node Slurm up in %.1f s" % (time.time() - t0))

        # 1. the job array and its merge equal one render on this machine
        out = os.path.join(work, "array")
        array_id, merge_id = submit(cluster, script, qrm, 3, out, FLAGS)
        state = cluster.wait_job(merge_id)
        if state != "COMPLETED":
            cluster.fail("merge job %s ended %s" % (merge_id, state))
        whole = os.path.join(work, "whole")
        r = subprocess.run([qrm, "render", *FLAGS, "--out", whole], capture_output=True, text=True)
        if r.returncode != 0:
            cluster.fail("single render failed: " + r.stderr)
        names = sorted(f for f in os.listdir(whole))
        merged = sorted(f for f in os.listdir(out) if os.path.isfile(os.path.join(out, f)))
        if names != merged:
            cluster.fail("merged files %s, single render %s" % (merged, names))
        for f in names:
            a, b = os.path.join(out, f), os.path.join(whole, f)
            same = summary_results(a) == summary_results(b) if f.endswith(".json") else \
                open(a, "rb").read() == open(b, "rb").read()
            if not same:
                cluster.fail("%s: the job array's merge differs from the single render" % f)
        print("job array %s (3 tasks) + merge %s: %d files byte-identical to a single render, %.1f s"
              % (array_id, merge_id, len(names), time.time() - t0))

        # 2. a failing array cancels its merge job
        t1 = time.time()
        bad = os.path.join(work, "failing")
        array_id, merge_id = submit(cluster, script, qrm, 2, bad, ["--scene", "no_such_scene"])
        state = cluster.wait_job(merge_id)
        if state != "CANCELLED":
            cluster.fail("merge job %s after failed tiles ended %s, not CANCELLED" % (merge_id, state))
        task_states = {cluster.job_state("%s_%d" % (array_id, i)) for i in range(2)}
        if task_states != {"FAILED"}:
            cluster.fail("tasks of failing array %s: %s" % (array_id, task_states))
        if any(os.path.isfile(os.path.join(bad, f)) for f in os.listdir(bad)):
            cluster.fail("a failed array left merged files in %s" % bad)
        print("failing array %s: tasks FAILED, merge %s CANCELLED, %.1f s" % (array_id, merge_id, time.time() - t1))
    finally:
        cluster.stop()
        shutil.rmtree(cluster.root, ignore_errors=True)
    print("slurm job array: as promised")


if __name__ == "__main__":
    main()
