"""The test runner's clean-up check (scripts/run_tests.py): every job runs with a TMPDIR of its own,
what a job leaves there fails it by name, and the directories go away whatever the job did."""
import glob
import importlib.util
import os
import re
import textwrap

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
    assert os.listdir(temp.root) == []


def test_leftovers_fail_the_job_by_name_and_are_removed(temp):
    p, f, s, x, rc, log, _, left = run_tests.run_in_tmpdir(temp, job_writing("b.csv", "a_dir"), None, 10)
    assert (p, f, left) == (1, 1, ["a_dir", "b.csv"])
    with open(log) as fh:
        assert "left in its TMPDIR: a_dir, b.csv" in fh.read()
    assert os.listdir(temp.root) == []


def test_allowed_leftovers_do_not_fail_but_are_removed(temp):
    p, f, s, x, rc, log, _, left = run_tests.run_in_tmpdir(temp, job_writing("ray", "runtime-ci"), None, 10)
    assert (f, left) == (0, [])
    assert os.listdir(temp.root) == []


def test_a_job_that_raises_still_has_its_directory_removed(temp):
    def job(_path, _timeout, tmpdir, _scratch):
        open(os.path.join(tmpdir, "x"), "w").close()
        raise RuntimeError("boom")
    with pytest.raises(RuntimeError):
        run_tests.run_in_tmpdir(temp, job, None, 10)
    assert os.listdir(temp.root) == []


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
    assert os.listdir(temp.root) == []


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
