"""camera_renderer's watcher (modrob_viz.render.supervisor) with real child processes: restarted
after a crash signal, not after any other end, bounded, and signals passed on."""
import os
import signal
import subprocess
import sys
import textwrap

import pytest

from modrob_viz.render import supervisor

# a child that dies of SIGSEGV for its first ``crashes`` starts (counted in a file), then exits with
# ``code``; it writes its CHILD_ENV so the test sees what the watcher gave it
CHILD = textwrap.dedent("""
    import os, signal, sys, time
    count_file, crashes, code = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    n = int(open(count_file).read()) if os.path.exists(count_file) else 0
    open(count_file, "w").write(str(n + 1))
    open(count_file + ".env", "w").write(os.environ.get("MODROB_RENDERER_CHILD", ""))
    if n < crashes:
        os.kill(os.getpid(), signal.SIGSEGV)
    if code == 99:              # wait to be stopped
        open(count_file + ".ready", "w").write("1")
        time.sleep(60)
    sys.exit(code)
""")


def run(tmp_path, crashes, code, restarts=3):
    script = tmp_path / "child.py"
    script.write_text(CHILD)
    count = tmp_path / "count"
    logs = []
    rc = supervisor.supervise([sys.executable, str(script), str(count), str(crashes), str(code)],
                              restarts=restarts, log=logs.append)
    return rc, int(count.read_text()), logs, (tmp_path / "count.env").read_text()


def test_restarted_after_a_crash_signal_and_ends_with_the_childs_code(tmp_path):
    rc, starts, logs, env = run(tmp_path, crashes=2, code=0)
    assert (rc, starts) == (0, 3)
    assert env == "1"
    assert len(logs) == 2 and "SIGSEGV" in logs[0] and "restart 1 of 3" in logs[0]


def test_restarts_are_bounded(tmp_path):
    rc, starts, logs, _ = run(tmp_path, crashes=10, code=0, restarts=2)
    assert (rc, starts) == (128 + signal.SIGSEGV, 3)
    assert "giving up" in logs[-1]


def test_other_ends_are_not_restarted(tmp_path):
    rc, starts, logs, _ = run(tmp_path, crashes=0, code=2)
    assert (rc, starts, logs) == (2, 1, [])


def test_restarts_setting_is_checked():
    assert supervisor.restarts_allowed({}) == 3
    assert supervisor.restarts_allowed({supervisor.RESTARTS_ENV: "0"}) == 0
    for bad in ("-1", "many"):
        with pytest.raises(ValueError, match=supervisor.RESTARTS_ENV):
            supervisor.restarts_allowed({supervisor.RESTARTS_ENV: bad})


def test_sigint_is_passed_on_and_not_followed_by_a_restart(tmp_path):
    """The watcher as its own process (as roslaunch runs it): SIGINT reaches the child, which
    ends; the watcher exits with the child's end and starts nothing more."""
    script = tmp_path / "child.py"
    script.write_text(CHILD)
    count = tmp_path / "count"
    watcher = subprocess.Popen(
        [sys.executable, "-c", "import sys; from modrob_viz.render import supervisor; "
         "sys.exit(supervisor.supervise(sys.argv[1:], log=lambda t: None))",
         sys.executable, str(script), str(count), "0", "99"], env=dict(os.environ))
    ready = tmp_path / "count.ready"
    try:
        for _ in range(600):
            if ready.exists():
                break
            try:
                watcher.wait(0.05)
                break
            except subprocess.TimeoutExpired:
                pass
        assert ready.exists(), "the child did not start"
        watcher.send_signal(signal.SIGINT)
        rc = watcher.wait(30)
    finally:
        if watcher.poll() is None:
            watcher.kill()
    assert rc != 0                   # the child ended by the signal (KeyboardInterrupt)
    assert int(count.read_text()) == 1
