"""The test runner's clean-up check (scripts/run_tests.py): every job runs with a TMPDIR of its own,
what a job leaves there fails it by name, and the directories go away whatever the job did, when
the run is stopped by SIGTERM, and (at the next run's start) when the run was killed."""
import glob
import importlib.util
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import textwrap
import time

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("run_tests", os.path.join(HERE, "..", "run_tests.py"))
run_tests = importlib.util.module_from_spec(spec)
spec.loader.exec_module(run_tests)


@pytest.fixture
def temp(tmp_path, monkeypatch):
    monkeypatch.setattr(run_tests.tempfile, "tempdir", None)     # gettempdir() reads TMPDIR again
    monkeypatch.setenv("TMPDIR", str(tmp_path))                    # the run's directory goes in here
    monkeypatch.setattr(run_tests, "RESULTS", str(tmp_path / "results"))
    monkeypatch.setattr(run_tests, "ROS_HOME", str(tmp_path / "results" / "ros_home"))
    t = run_tests.TempDirs()
    yield t
    t.close()


def job_writing(*names):
    """A job that leaves ``names`` in its TMPDIR and passes its one test."""
    def job(_path, _timeout, tmpdir, scratch):
        assert os.listdir(tmpdir) == [] and os.path.isdir(scratch)
        for name in names:
            open(os.path.join(tmpdir, name), "w").close()
        os.makedirs(run_tests.RESULTS, exist_ok=True)
        log = os.path.join(run_tests.RESULTS, "job.log")
        open(log, "w").close()
        return 1, 0, 0, 0, 0, log, 0.1
    return job


def test_the_run_directory_is_short_and_each_job_gets_a_fresh_one(temp):
    assert os.path.basename(temp.root).startswith("modrob-test-")
    assert len(temp.root) <= run_tests.TempDirs.LONGEST_BASE + len("/modrob-test-12345678")
    first, _ = temp.new()
    second, _ = temp.new()
    assert first != second and os.listdir(first) == os.listdir(second) == []


def test_a_long_system_tmpdir_is_not_used(tmp_path, monkeypatch):
    long_dir = tmp_path / ("x" * run_tests.TempDirs.LONGEST_BASE)
    long_dir.mkdir()
    monkeypatch.setattr(run_tests.tempfile, "tempdir", None)     # gettempdir() reads TMPDIR again
    monkeypatch.setenv("TMPDIR", str(long_dir))
    t = run_tests.TempDirs()
    try:
        assert os.path.dirname(t.root) == "/tmp"
    finally:
        t.close()


def test_a_job_that_leaves_nothing_passes_and_its_directory_goes(temp):
    p, f, s, x, rc, log, _, left = run_tests.run_in_tmpdir(temp, job_writing(), None, 10)
    assert (p, f, left) == (1, 0, [])
    assert os.listdir(temp.root) == [run_tests.TempDirs.OWNER]     # the job's directories are gone


def test_leftovers_fail_the_job_by_name_and_are_removed(temp):
    p, f, s, x, rc, log, _, left = run_tests.run_in_tmpdir(temp, job_writing("b.csv", "a_dir"), None, 10)
    assert (p, f, left) == (1, 1, ["a_dir", "b.csv"])
    with open(log) as fh:
        assert "left in its TMPDIR: a_dir, b.csv" in fh.read()
    assert os.listdir(temp.root) == [run_tests.TempDirs.OWNER]     # the job's directories are gone


def test_allowed_leftovers_do_not_fail_but_are_removed(temp):
    p, f, s, x, rc, log, _, left = run_tests.run_in_tmpdir(temp, job_writing("runtime-ci"), None, 10)
    assert (f, left) == (0, [])
    assert os.listdir(temp.root) == [run_tests.TempDirs.OWNER]     # the job's directories are gone


def test_a_job_that_raises_still_has_its_directory_removed(temp):
    def job(_path, _timeout, tmpdir, _scratch):
        open(os.path.join(tmpdir, "x"), "w").close()
        raise RuntimeError("boom")
    with pytest.raises(RuntimeError):
        run_tests.run_in_tmpdir(temp, job, None, 10)
    assert os.listdir(temp.root) == [run_tests.TempDirs.OWNER]     # the job's directories are gone


def test_close_names_what_was_still_there_and_removes_the_run_directory(temp):
    tmpdir, _ = temp.new()               # a job that never ended
    assert temp.close() == ["1", "1-runner"]
    assert not os.path.exists(temp.root)


def test_a_real_pytest_job_sees_its_tmpdir_and_its_tmp_path_is_not_a_leftover(temp, tmp_path):
    tests = tmp_path / "pkg"
    tests.mkdir()
    (tests / "test_files.py").write_text(textwrap.dedent("""\
        import os, tempfile

        def test_cleans_up(tmp_path):
            (tmp_path / "made_by_tmp_path").write_text("x")     # pytest's, removed by the runner
            with tempfile.TemporaryDirectory() as d:
                assert d.startswith(os.environ["TMPDIR"])

        def test_leaks():
            open(os.path.join(tempfile.gettempdir(), "leaked.txt"), "w").close()
        """))
    p, f, s, x, rc, log, _, left = run_tests.run_in_tmpdir(temp, run_tests.run_unit, str(tests), 120)
    assert (p, f, left) == (2, 1, ["leaked.txt"]), open(log).read()
    assert os.listdir(temp.root) == [run_tests.TempDirs.OWNER]     # the job's directories are gone


@pytest.fixture
def short_base():
    """A directory of the test's own for the runner to use as the system's temporary directory:
    within TempDirs.LONGEST_BASE (a longer one would make it fall back to /tmp)."""
    base = tempfile.mkdtemp(prefix="t", dir=tempfile.gettempdir())
    try:
        assert len(base) <= run_tests.TempDirs.LONGEST_BASE, "TMPDIR %s is too long for this test" % base
        yield base
    finally:
        shutil.rmtree(base, ignore_errors=True)


def dead_pid():
    proc = subprocess.Popen([sys.executable, "-c", ""])
    proc.wait()
    return proc.pid


def test_a_run_removes_the_directories_of_killed_runs_and_nothing_else(short_base, monkeypatch, capsys):
    monkeypatch.setattr(run_tests.tempfile, "tempdir", None)     # gettempdir() reads TMPDIR again
    monkeypatch.setenv("TMPDIR", short_base)

    def run_dir(name, pid):
        """A run's directory with a job's TMPDIR in it, owned by ``pid`` (None: no owner file)."""
        path = os.path.join(short_base, name)
        os.makedirs(os.path.join(path, "3"))
        open(os.path.join(path, "3", "left.txt"), "w").close()
        if pid is not None:
            with open(os.path.join(path, run_tests.TempDirs.OWNER), "w") as fh:
                fh.write("%s\n" % pid)
        return path
    gone = dead_pid()
    killed = run_dir("modrob-test-killed01", gone)
    kept = [run_dir("modrob-test-running1", os.getpid()),     # a live run's
            run_dir("modrob-test-starting", None),            # no owner yet, or not a run's
            run_dir("modrob-test-garbled1", "12ab"),
            run_dir("other-dir-of-a-dead", gone),             # not named as the runner names its own
            run_dir("elsewhere", gone)]
    link = os.path.join(short_base, "modrob-test-symlink1")  # a link to a dead run's directory
    os.symlink(kept[-1], link)
    kept.append(link)
    if os.getuid() == 0:                                      # another user's (only root can make one)
        kept.append(run_dir("modrob-test-otheruser", gone))
        for root, dirs, files in os.walk(kept[-1]):
            for name in [root] + [os.path.join(root, n) for n in dirs + files]:
                os.chown(name, 65534, 65534)
    temp = run_tests.TempDirs()
    try:
        out = capsys.readouterr().out
        assert not os.path.exists(killed)
        assert [p for p in kept if not os.path.lexists(p)] == []
        assert os.path.exists(os.path.join(kept[-1], run_tests.TempDirs.OWNER))
        assert len(out.splitlines()) == 1 and "removed 1 temporary directory" in out
        assert killed in out and str(kept) not in out
        with open(os.path.join(temp.root, run_tests.TempDirs.OWNER)) as fh:
            assert int(fh.read()) == os.getpid()
        second = run_tests.TempDirs()          # the first run is alive: its directory stays
        second.close()
        assert os.path.isdir(temp.root) and capsys.readouterr().out == ""
    finally:
        temp.close()
    assert not os.path.exists(temp.root)


WAITING_JOB = textwrap.dedent("""\
    import os, signal, subprocess, sys, tempfile

    def test_runs_until_the_runner_stops_it():
        open(os.path.join(tempfile.gettempdir(), "made-by-the-job"), "w").close()
        child = subprocess.Popen([sys.executable, "-c", "import signal; signal.pause()"])
        path = os.environ["JOB_PIDS"]
        with open(path + ".new", "w") as fh:
            fh.write("%d %d" % (os.getpid(), child.pid))
        os.rename(path + ".new", path)
        signal.pause()
    """)


def running(pid):
    """Whether process ``pid`` exists and is not a zombie (dead, waiting for its parent)."""
    try:
        with open("/proc/%d/stat" % pid) as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP])
def test_sigterm_stops_the_jobs_removes_the_directories_and_exits_143(tmp_path, short_base, signum):
    """The runner (a copy, in a workspace whose one unit test runs until it is stopped) is sent
    SIGTERM as CI or `timeout` would (or SIGHUP, as when its terminal closes): the job and its
    child end, nothing is left, exit 128 + the signal's number (143 for SIGTERM)."""
    ws = tmp_path / "ws"
    (ws / "scripts").mkdir(parents=True)
    shutil.copy(os.path.join(HERE, "..", "run_tests.py"), str(ws / "scripts"))
    unit = ws / "src" / "fakepkg" / "test" / "unit"
    unit.mkdir(parents=True)
    (unit / "test_wait.py").write_text(WAITING_JOB)
    pids = tmp_path / "pids"
    runner = [sys.executable, str(ws / "scripts" / "run_tests.py"), "--tier", "1", "-k", "fakepkg"]
    proc = subprocess.Popen(runner, env=dict(os.environ, TMPDIR=short_base, JOB_PIDS=str(pids)),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        deadline = time.monotonic() + 60
        while not pids.exists():                 # until the job runs
            assert proc.poll() is None, "the runner ended before its job started:\n" + proc.stdout.read()
            assert time.monotonic() < deadline, "the job did not start within 60 s"
            time.sleep(0.05)
        run_dirs = glob.glob(os.path.join(short_base, "modrob-test-*"))
        assert len(run_dirs) == 1 and os.listdir(os.path.join(run_dirs[0], "1")) == ["made-by-the-job"]
        proc.send_signal(signum)
        out, _ = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    job, child = (int(v) for v in pids.read_text().split())
    try:
        assert proc.returncode == 128 + signum, out
        assert ("[tests] terminated by %s: the running jobs were stopped and %s removed"
                % (signal.Signals(signum).name, run_dirs[0]) in out)
        assert os.listdir(short_base) == []
        assert not running(job)                      # the runner waited for it
        deadline = time.monotonic() + 10             # the child got the SIGINT as well: it ends on its own
        while running(child) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not running(child), "the job's child %d is still running" % child
    finally:                                         # when it failed: stop what the runner left
        for pid in (job, child):
            if running(pid):
                os.kill(pid, signal.SIGKILL)


IGNORES_SIGINT = "import signal; signal.signal(signal.SIGINT, signal.SIG_IGN); signal.pause()"


@pytest.mark.parametrize("code, how", [("import signal; signal.pause()", "ends on SIGINT"),
                                       (IGNORES_SIGINT, "ignores SIGINT: killed after the grace time")])
def test_a_job_past_its_timeout_is_stopped(code, how):
    procs = run_tests.JobProcesses()
    procs.GRACE_S = 0.5
    start = time.monotonic()
    assert procs.call([sys.executable, "-c", code], 1) == "timeout after 1 s", how
    assert time.monotonic() - start < 10 and procs.running == set()


# Fixed paths of the X server's, not temporary files: they are the same whatever TMPDIR says.
X_PATHS = re.compile(r"/tmp/\.X(11-unix|%d-lock|\d)")
HARD_CODED_TMP = re.compile(r"""["'=]/tmp(/|["'])""")


def test_no_test_writes_to_a_hard_coded_tmp():
    """The runner's check sees only TMPDIR: a test that names /tmp itself escapes it (use tmp_path,
    tempfile, or $ROS_HOME/test_output for what a person should see)."""
    root = run_tests.ROOT
    files = [f for pattern in ("src/*/test/**/*", "scripts/*.py", "scripts/test/*.py")
             for f in glob.glob(os.path.join(root, pattern), recursive=True)
             if os.path.isfile(f) and f.endswith((".py", ".test", ".launch", ".sh", ".yaml", ".xml"))]
    assert len(files) > 100
    found = []
    for path in files:
        with open(path, errors="replace") as fh:
            for n, line in enumerate(fh, 1):
                if HARD_CODED_TMP.search(X_PATHS.sub("", line)):
                    found.append("%s:%d: %s" % (os.path.relpath(path, root), n, line.strip()))
    found = [f for f in found if not f.startswith(("scripts/run_tests.py", "scripts/test/test_run_tests.py"))]
    assert found == [], "\n".join(found)
