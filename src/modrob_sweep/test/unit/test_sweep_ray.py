"""The runner end to end on a local Ray with two workers, through the `sweep` command, with the
slide scenario (a real /gazebo world per trial, a few seconds each): eight trials of which one
crashes and one hangs; the same trials one after another give identical results; Ctrl-C leaves no
process of the sweep behind (trials, roscores, simulators, nor the Ray it started)."""
import os
import signal
import subprocess
import sys
import time
import uuid

import pytest
import yaml

from modrob_sim.procs import alive

pd = pytest.importorskip("pandas")

SWEEP = [os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "scripts",
                      "sweep")]
POINTS = [{"mu": 0.2, "fault": "hang"},       # first, so that its timeout runs beside the others
          {"mu": 0.05, "fault": "none"}, {"mu": 0.1, "fault": "none"}, {"mu": 0.2, "fault": "crash"},
          {"mu": 0.2, "fault": "none"}, {"mu": 0.4, "fault": "none"}, {"mu": 0.8, "fault": "none"},
          {"mu": 0.3, "fault": "none"}]
COMPARED = ["distance", "rest_time", "v0", "sim_s", "seed", "mu"]


def write_sweep(folder, name, points, timeout_s):
    data = {"name": name,
            "scenario": {"launch": ["modrob_sweep", "slide_trial.launch"],
                         "args": ["mu:={mu}", "v0:=0.8", "jitter:=0.05", "seed:={seed}", "fault:={fault}",
                                  "max_time:=2.0", "result_file:={out}/result.yaml"]},
            "result": {"file": "result.yaml", "success": "success", "sim_time": "sim_time",
                       "metrics": ["distance", "rest_time", "v0"]},
            "parameters": {"points": points}, "repetitions": 1, "seed": 3, "timeout_s": timeout_s, "cpus": 1}
    path = os.path.join(folder, name + ".yaml")
    with open(path, "w") as fh:
        yaml.safe_dump(data, fh)
    return path


def processes_of(name):
    """pids of processes that belong to the sweep ``name`` (its trials, or the Ray it started)."""
    marks = [("MODROB_SWEEP_ID=%s-" % name).encode(), ("MODROB_SWEEP_TRIAL=%s-" % name).encode()]
    out = []
    for e in os.listdir("/proc"):
        if not e.isdigit():
            continue
        try:
            with open("/proc/%s/environ" % e, "rb") as fh:
                env = fh.read().split(b"\0")
        except OSError:
            continue
        if not alive(e):
            continue
        if any(v.startswith(m) for v in env for m in marks):
            out.append(int(e))
    return out


def cmdlines(pids):
    out = []
    for p in pids:
        try:
            with open("/proc/%d/cmdline" % p, "rb") as fh:
                out.append(fh.read().replace(b"\0", b" ").decode(errors="replace")[:100])
        except OSError:
            pass
    return out


def run_sweep(args, timeout):
    proc = subprocess.run([sys.executable] + SWEEP + args, capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return proc


def test_eight_trials_on_two_workers_crash_hang_and_sequential_identity(tmp_path):
    name = "test_sweep_%s" % uuid.uuid4().hex[:8]
    path = write_sweep(str(tmp_path), name, POINTS, timeout_s=40)
    par = run_sweep([path, "--workers", "2", "--out", str(tmp_path / "parallel")], timeout=600)
    assert "2 side by side" in par.stdout and "ETA" in par.stdout
    df = pd.read_csv(tmp_path / "parallel" / "trials.csv")
    assert list(df.columns[:5]) == ["trial", "host", "outcome", "wall_s", "sim_s"]
    assert len(df) == 8 and list(df["trial"]) == list(range(8))
    by = df.set_index("trial")
    assert by.loc[0, "outcome"] == "timeout"
    assert by.loc[3, "outcome"] == "crashed" and "no result file" in by.loc[3, "detail"]
    normal = [k for k, p in enumerate(POINTS) if p["fault"] == "none"]
    assert set(by.loc[normal, "outcome"]) <= {"success", "failure"}
    # physics, not noise: a slipperier floor lets the puck slide further (v0 differs by the jitter only)
    d = by.loc[normal].sort_values("mu")["distance"].tolist()
    assert d == sorted(d, reverse=True) and d[0] > 0.4 and d[-1] < 0.1
    assert (by.loc[normal, "attempts"] == 1).all()
    assert by.loc[normal, "host"].nunique() == 1 and by.loc[0, "host"]
    summary = (tmp_path / "parallel" / "summary.md").read_text()
    assert "timeout 1" in summary and "crashed 1" in summary and "## Trials that did not succeed" in summary
    for png in ("success_vs_mu.png", "distance_vs_mu.png"):
        assert (tmp_path / "parallel" / png).stat().st_size > 1000
    assert processes_of(name) == [], cmdlines(processes_of(name))

    # the same trials one after another: identical numbers (the seed is the trial's, the physics stepped)
    seq = run_sweep([path, "--workers", "1", "--trials", ",".join(map(str, normal[:3])),
                     "--out", str(tmp_path / "sequential")], timeout=600)
    assert "1 side by side" in seq.stdout
    ds = pd.read_csv(tmp_path / "sequential" / "trials.csv").set_index("trial")
    assert list(ds.index) == normal[:3]
    for col in COMPARED:
        assert ds[col].tolist() == by.loc[normal[:3], col].tolist(), col


def test_ctrl_c_leaves_no_process_of_the_sweep(tmp_path):
    name = "test_sweep_int_%s" % uuid.uuid4().hex[:8]
    path = write_sweep(str(tmp_path), name, [{"mu": 0.2, "fault": "hang"}, {"mu": 0.3, "fault": "hang"},
                                             {"mu": 0.4, "fault": "none"}], timeout_s=300)
    proc = subprocess.Popen([sys.executable] + SWEEP + [path, "--workers", "2", "--out", str(tmp_path / "o")],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        # wait until both hanging trials have their simulator up (two /gazebo nodes of this sweep)
        deadline = time.monotonic() + 240
        while time.monotonic() < deadline:
            sims = [c for c in cmdlines(processes_of(name)) if "modrob_sim/gazebo" in c]
            if len(sims) >= 2:
                break
            assert proc.poll() is None, proc.stdout.read()
            time.sleep(0.2)
        else:
            raise AssertionError("the two trials did not start within 240 s: %s"
                                 % cmdlines(processes_of(name)))
        assert any("rosmaster" in c for c in cmdlines(processes_of(name)))
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, out[-3000:]
    assert "[sweep] interrupted: stopping 3 running trial(s)" in out
    # the trials' reapers stopped them, not the driver's last-resort sweep of the machine
    assert "left on this machine" not in out, out[-2000:]
    assert processes_of(name) == [], cmdlines(processes_of(name))


class _Ray(object):
    """A stand-in for the ray module whose local node fails to start ``failures`` times."""

    def __init__(self, failures):
        self.failures, self.inits, self.shutdowns = failures, 0, 0
        self.temp_dirs = []

    def init(self, **kw):
        self.inits += 1
        assert os.path.isdir(kw["_temp_dir"]) and os.environ["RAY_TMPDIR"] == kw["_temp_dir"]
        self.temp_dirs.append(kw["_temp_dir"])
        if self.inits <= self.failures:
            raise Exception("The current node timed out during startup. This could happen because ...")

    def shutdown(self):
        self.shutdowns += 1

    def is_initialized(self):
        return self.inits > self.failures and self.shutdowns < self.inits

    def cluster_resources(self):
        return {"CPU": 2.0}


@pytest.mark.parametrize("failures", [1, 2])
def test_a_local_ray_that_times_out_at_start_is_tried_once_more(monkeypatch, capsys, failures):
    from modrob_sweep import SweepError, runner
    fake = _Ray(failures)
    monkeypatch.setitem(sys.modules, "ray", fake)
    ray_tmpdir = os.environ.get("RAY_TMPDIR")
    if failures == 1:
        assert runner.connect(workers=2) == 2.0
        assert "trying once more" in capsys.readouterr().err
    else:
        with pytest.raises(SweepError, match="twice: The current node timed out"):
            runner.connect(workers=2)
    assert (fake.inits, fake.shutdowns) == (2, failures)
    # both attempts had the same temporary directory; shutdown() (or the failure) removes it
    assert len(set(fake.temp_dirs)) == 1
    runner.shutdown()
    assert not os.path.exists(fake.temp_dirs[0]) and os.environ.get("RAY_TMPDIR") == ray_tmpdir


def test_ray_temp_dir_is_short_enough_for_its_sockets(monkeypatch, capsys):
    """Ray's socket paths in it stay within the 107 bytes of a Unix socket; a longer base gives SHORT_TEMP."""
    from modrob_sweep import runner
    monkeypatch.delenv("RAY_TMPDIR", raising=False)
    path = runner.new_ray_temp_dir()
    try:
        assert len(path) + runner.RAY_SOCKET_TAIL <= runner.SOCKET_PATH_MAX, path
    finally:
        runner.shutdown()
    assert not os.path.exists(path)
    long_base = os.path.join(os.path.dirname(path), "x" * 40)
    os.mkdir(long_base)
    try:
        monkeypatch.setenv("RAY_TMPDIR", long_base)
        path = runner.new_ray_temp_dir()
        try:
            assert os.path.dirname(path) == runner.SHORT_TEMP
            assert "too long for Ray's socket paths" in capsys.readouterr().err
        finally:
            runner.shutdown()
    finally:
        os.rmdir(long_base)
    assert not os.path.exists(path) and os.environ["RAY_TMPDIR"] == long_base


@pytest.fixture
def ray_tmpdir():
    """A RAY_TMPDIR of the test's own, short enough for Ray's socket paths (the sweep's Ray makes its
    ``ray-*`` directory in it, not in SHORT_TEMP); the tests assert what is left in it."""
    import tempfile
    from modrob_sweep import runner
    path = tempfile.mkdtemp(prefix="rt", dir=tempfile.gettempdir())
    if len(path) > runner.RAY_TEMP_BASE_MAX:
        os.rmdir(path)
        path = tempfile.mkdtemp(prefix="rt", dir=runner.SHORT_TEMP)
    assert len(path) <= runner.RAY_TEMP_BASE_MAX, path
    yield path
    import shutil
    shutil.rmtree(path, ignore_errors=True)


def start_sweep(tmp_path, name, ray_tmpdir):
    """A one-trial sweep in a subprocess whose Ray goes to ``ray_tmpdir``."""
    path = write_sweep(str(tmp_path), name, [{"mu": 0.2, "fault": "none"}], timeout_s=120)
    env = dict(os.environ, RAY_TMPDIR=ray_tmpdir)
    return subprocess.Popen([sys.executable] + SWEEP + [path, "--workers", "1", "--out", str(tmp_path / "o")],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def ray_started(proc, name):
    """The sweep's Ray has started processes (ray.init is under way, or done); fails the test when
    the sweep has ended instead."""
    assert proc.poll() is None, proc.stdout.read()
    return processes_of(name)


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_while_ray_starts_stops_it(tmp_path, ray_tmpdir, signum):
    """ray.init spends seconds in Ray's C++ start-up, where Python runs no signal handler (and Ray's
    crash handler ended the process on SIGTERM): the signal stops the start, its processes and its
    directory there and then, and the sweep ends with 130."""
    from modrob_sim.waits import wait_until
    name = "test_sweep_start_%s" % uuid.uuid4().hex[:8]
    proc = start_sweep(tmp_path, name, ray_tmpdir)
    try:
        wait_until(lambda: ray_started(proc, name), 120, "the first process of the sweep's Ray")
        assert len(os.listdir(ray_tmpdir)) == 1         # its directory, which is to go
        proc.send_signal(signum)
        out, _ = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, out[-3000:]
    assert "[sweep] %s while Ray was starting: stopping it" % signum.name in out, out[-3000:]
    assert "[sweep] test_sweep_start_" not in out          # no trial was submitted
    wait_until(lambda: not processes_of(name), 30, "no process of the sweep left")
    assert os.listdir(ray_tmpdir) == []


def test_the_ray_directory_of_a_sweep_killed_with_sigkill_is_removed_by_the_next(tmp_path, ray_tmpdir,
                                                                                 monkeypatch, capsys):
    """SIGKILL leaves no chance to clean up: the Ray directory stays (and some of Ray's agents, for a
    minute); the next sweep that makes its Ray directory in the same place removes it and stops them."""
    from modrob_sim.waits import wait_until
    from modrob_sweep import runner
    name = "test_sweep_kill_%s" % uuid.uuid4().hex[:8]
    proc = start_sweep(tmp_path, name, ray_tmpdir)
    try:
        wait_until(lambda: ray_started(proc, name), 120, "the first process of the sweep's Ray")
        proc.kill()
        proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    left = os.listdir(ray_tmpdir)
    assert len(left) == 1 and left[0].startswith(runner.RAY_TEMP_PREFIX), left
    stale = os.path.join(ray_tmpdir, left[0])
    monkeypatch.setenv("RAY_TMPDIR", ray_tmpdir)
    path = runner.new_ray_temp_dir()            # what the next sweep does before its ray.init
    try:
        assert os.listdir(ray_tmpdir) == [os.path.basename(path)]
        assert "removed %s, the Ray directory of process %d" % (stale, proc.pid) in capsys.readouterr().err
        wait_until(lambda: not processes_of(name), 30, "no process of the killed sweep left")
    finally:
        runner.shutdown()
    assert os.listdir(ray_tmpdir) == []


def test_only_ray_directories_of_ended_processes_are_removed(tmp_path):
    from modrob_sim.procs import start_time
    from modrob_sweep import runner
    ended = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    ended_start = start_time(ended.pid)
    ended.kill()
    ended.wait()

    def ray_dir(name, owner):
        path = tmp_path / name
        (path / "session_latest").mkdir(parents=True)
        if owner:
            (path / runner.OWNER_FILE).write_text("%d %d\n" % owner)
        return path
    stale = ray_dir("ray-stale", (ended.pid, ended_start))
    reused = ray_dir("ray-reused", (os.getpid(), start_time(os.getpid()) - 1))  # a pid since reused
    mine = ray_dir("ray-mine", (os.getpid(), start_time(os.getpid())))
    foreign = ray_dir("ray-foreign", None)                  # not made by a sweep: not ours to judge
    other = ray_dir("other", (ended.pid, ended_start))
    assert sorted(runner.remove_stale_ray_temp_dirs(str(tmp_path))) == sorted([str(stale), str(reused)])
    assert sorted(os.listdir(tmp_path)) == sorted(p.name for p in (mine, foreign, other))


CRASHING_DRIVER = """
import os, signal, sys
import ray
from modrob_sweep import runner
token = sys.argv[2]
runner.connect(workers=1, token=token)

@ray.remote(max_retries=0)
def crash():
    os.kill(os.getpid(), signal.SIGSEGV)
try:
    ray.get(crash.remote())
except ray.exceptions.WorkerCrashedError as exc:
    # one write: Ray's log thread prints the raylet's lines to this stdout too, and print() writes
    # its pieces one by one, so a raylet line could come between "lost:" and the name
    sys.stdout.write("lost: %s\\n" % type(exc).__name__)
    sys.stdout.flush()
runner._wait_local_trials(token)
runner.keep_crash_logs(sys.argv[1], sys.stdout)
runner.shutdown(token)
"""


def test_a_crashed_ray_worker_leaves_its_stack_trace_in_the_results(tmp_path, ray_tmpdir):
    """Ray's crash handler is on (it was switched off once, and a worker's segmentation fault then left
    no trace anywhere): the dead worker's log, with the stack, is kept beside the results."""
    token = "test_crash_%s" % uuid.uuid4().hex[:8]
    proc = subprocess.run([sys.executable, "-c", CRASHING_DRIVER, str(tmp_path / "results"), token],
                          env=dict(os.environ, RAY_TMPDIR=ray_tmpdir), capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    assert "lost: WorkerCrashedError" in proc.stdout
    kept = os.listdir(tmp_path / "results" / "ray_crash_logs")
    assert len(kept) == 1 and kept[0].startswith("worker-") and kept[0].endswith(".err"), kept
    log = (tmp_path / "results" / "ray_crash_logs" / kept[0]).read_text()
    assert "*** SIGSEGV received at time=" in log and "in crash" in log, log[-2000:]
    assert proc.stdout.count("a Ray process crashed: its log with the stack trace is in %s" % (
        tmp_path / "results" / "ray_crash_logs" / kept[0])) == 1, proc.stdout
    assert os.listdir(ray_tmpdir) == []
