"""A single-node Slurm cluster on localhost for the tests: Debian's munge and slurm-wlm,
everything in a temporary folder, no systemd, no accounting. Started by `with SlurmCluster()
as cluster:`; every daemon is stopped by its PID on leaving, also when the test fails."""

import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class SlurmCluster:
    def __init__(self, cpus=None):
        self.cpus = cpus or os.cpu_count() or 1
        self.pids = []  # (name, pid) in start order
        self.procs = []
        self.dir = None
        self.env = None

    def _log(self, name):
        path = os.path.join(self.dir, "log", name)
        return open(path, "w")

    def __enter__(self):
        try:
            self._start()
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc):
        self.stop()
        return False

    def _start(self):
        for exe in ("mungekey", "munged", "slurmctld", "slurmd", "sbatch", "squeue"):
            if shutil.which(exe) is None and not os.path.exists("/usr/sbin/" + exe):
                raise RuntimeError("%s not found: install munge and slurm-wlm "
                                   "(scripts/install-deps.sh)" % exe)
        self.dir = tempfile.mkdtemp(prefix="dhdr-slurm-")
        os.chmod(self.dir, 0o755)  # munged checks that its socket's folders are reachable
        for sub in ("munge", "state", "spool", "log"):
            os.makedirs(os.path.join(self.dir, sub))
        munge = os.path.join(self.dir, "munge")
        key = os.path.join(munge, "munge.key")
        subprocess.run(["/usr/sbin/mungekey", "--create", "--keyfile=" + key], check=True,
                       capture_output=True)
        shutil.chown(munge, "munge", "munge")
        shutil.chown(key, "munge", "munge")
        os.chmod(key, 0o600)
        self.socket = os.path.join(munge, "munge.socket")
        pidfile = os.path.join(munge, "munged.pid")
        # munged forks into the background and leaves its PID in the file.
        subprocess.run(["runuser", "-u", "munge", "--", "/usr/sbin/munged",
                        "--socket=" + self.socket, "--key-file=" + key,
                        "--pid-file=" + pidfile, "--log-file=" + os.path.join(munge, "log"),
                        "--seed-file=" + os.path.join(munge, "seed")], check=True,
                       capture_output=True)
        self._wait_for(lambda: os.path.exists(pidfile) and os.path.exists(self.socket),
                       "munged's socket")
        with open(pidfile) as f:
            self.pids.append(("munged", int(f.read().strip())))

        ctld, slurmd = _free_port(), _free_port()
        conf = os.path.join(self.dir, "slurm.conf")
        with open(conf, "w") as f:
            f.write("\n".join([
                "ClusterName=dhdrtest",
                "SlurmctldHost=localhost(127.0.0.1)",
                "SlurmctldPort=%d" % ctld,
                "SlurmdPort=%d" % slurmd,
                "SlurmUser=root",
                "AuthType=auth/munge",
                "AuthInfo=socket=%s" % self.socket,
                "CredType=cred/munge",
                "StateSaveLocation=%s/state" % self.dir,
                "SlurmdSpoolDir=%s/spool" % self.dir,
                "SlurmctldPidFile=%s/slurmctld.pid" % self.dir,
                "SlurmdPidFile=%s/slurmd.pid" % self.dir,
                "SlurmctldLogFile=%s/log/slurmctld.log" % self.dir,
                "SlurmdLogFile=%s/log/slurmd.log" % self.dir,
                "ProctrackType=proctrack/linuxproc",
                "TaskPlugin=task/none",
                "SelectType=select/cons_tres",
                "SelectTypeParameters=CR_CPU",
                "AccountingStorageType=accounting_storage/none",
                "JobAcctGatherType=jobacct_gather/none",
                "JobCompType=jobcomp/none",
                "MpiDefault=none",
                "ReturnToService=2",
                "MailProg=/bin/true",
                "NodeName=localhost NodeAddr=127.0.0.1 CPUs=%d State=UNKNOWN" % self.cpus,
                "PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP",
                ""]))
        self.env = dict(os.environ, SLURM_CONF=conf)
        for name, argv in (("slurmctld", ["/usr/sbin/slurmctld", "-D", "-i"]),
                           ("slurmd", ["/usr/sbin/slurmd", "-D", "-N", "localhost"])):
            with self._log(name + ".out") as log:
                p = subprocess.Popen(argv, env=self.env, stdout=log, stderr=subprocess.STDOUT,
                                     stdin=subprocess.DEVNULL, start_new_session=True)
            self.procs.append(p)
            self.pids.append((name, p.pid))
        self._wait_for(self._idle, "an idle node (logs in %s/log)" % self.dir, timeout=60)

    def _idle(self):
        for name, p in zip(("slurmctld", "slurmd"), self.procs):
            if p.poll() is not None:
                raise RuntimeError("%s exited with status %d (logs in %s/log)" % (
                    name, p.returncode, self.dir))
        out = subprocess.run(["sinfo", "-h", "-o", "%T"], env=self.env, capture_output=True,
                             text=True)
        return out.returncode == 0 and out.stdout.strip() == "idle"

    @staticmethod
    def _wait_for(ready, what, timeout=20.0):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if ready():
                return
            time.sleep(0.1)
        raise RuntimeError("timed out waiting for " + what)

    def stop(self):
        """scancel everything, then SIGTERM each daemon by PID (SIGKILL after 10 s)."""
        if self.env and self.procs and all(p.poll() is None for p in self.procs):
            subprocess.run(["scancel", "--full", "-u", "root"], env=self.env,
                           capture_output=True, timeout=30)
        for name, pid in reversed(self.pids):
            try:
                os.kill(pid, signal.SIGTERM)
            except ProcessLookupError:
                continue
            end = time.monotonic() + 10
            while time.monotonic() < end:
                proc = next((p for p in self.procs if p.pid == pid), None)
                if proc is not None:
                    if proc.poll() is not None:
                        break
                else:
                    try:
                        os.kill(pid, 0)
                    except ProcessLookupError:
                        break
                time.sleep(0.05)
            else:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
        self.pids = []
        self.procs = []
        # The folder holds the daemons' logs: kept when asked (DHDR_KEEP_SLURM=1).
        if self.dir and not os.environ.get("DHDR_KEEP_SLURM"):
            shutil.rmtree(self.dir, ignore_errors=True)
            self.dir = None
