"""The trial supervisor leaves nothing behind: processes that left the process group and session,
a trial told to stop, and the status it reports."""
import json
import os
import signal
import subprocess
import sys
import time
import uuid

from modrob_sim.procs import alive
from modrob_sweep.reaper import TOKEN_VAR

ESCAPE = r"""
import os, subprocess, sys
# a grandchild in its own session (as roslaunch starts the demos' masters), then the command ends
p = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(300)"], start_new_session=True)
open(sys.argv[1], "w").write(str(p.pid))
sys.exit(3)
"""

HANG = r"""
import os, subprocess, sys, time
p = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(300)"], start_new_session=True)
open(sys.argv[1], "w").write(str(p.pid))
time.sleep(300)
"""


def with_token(token):
    out = []
    for e in os.listdir("/proc"):
        if e.isdigit():
            try:
                with open("/proc/%s/environ" % e, "rb") as fh:
                    if ("%s=%s" % (TOKEN_VAR, token)).encode() in fh.read().split(b"\0"):
                        out.append(int(e))
            except OSError:
                pass
    return out


def reaper(tmp_path, code, token):
    status = str(tmp_path / "status.json")
    pidfile = str(tmp_path / "pid")
    cmd = [sys.executable, "-m", "modrob_sweep.reaper", "--token", token, "--parent", str(os.getpid()),
           "--status", status, "--", sys.executable, "-c", code, pidfile]
    return subprocess.Popen(cmd, start_new_session=True), status, pidfile


def wait_file(path, timeout=20.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if os.path.exists(path) and open(path).read():
            return open(path).read()
        time.sleep(0.02)
    raise AssertionError("%s not written within %g s" % (path, timeout))


def test_leftovers_of_a_finished_command_are_stopped_and_named(tmp_path):
    token = uuid.uuid4().hex
    proc, status, pidfile = reaper(tmp_path, ESCAPE, token)
    assert proc.wait(timeout=30) == 3
    grandchild = int(wait_file(pidfile))
    assert not alive(grandchild)
    st = json.load(open(status))
    assert st["exit"] == 3 and not st["stopped"] and st["infra"] is None
    assert len(st["leftovers"]) == 1 and "time.sleep(300)" in st["leftovers"][0]
    assert with_token(token) == []


def test_sigterm_stops_the_whole_trial(tmp_path):
    token = uuid.uuid4().hex
    proc, status, pidfile = reaper(tmp_path, HANG, token)
    grandchild = int(wait_file(pidfile))
    deadline = time.monotonic() + 20    # the grandchild may still be between fork and exec
    while len(with_token(token)) < 2 and time.monotonic() < deadline:
        time.sleep(0.05)
    assert alive(grandchild) and len(with_token(token)) == 2
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=30) == 128 + signal.SIGTERM
    assert not alive(grandchild)
    assert with_token(token) == []
    assert json.load(open(status))["stopped"] is True


def test_a_command_that_cannot_start_is_an_infrastructure_failure(tmp_path):
    status = str(tmp_path / "status.json")
    rc = subprocess.call([sys.executable, "-m", "modrob_sweep.reaper", "--token", "t", "--parent",
                          str(os.getpid()),
                          "--status", status, "--", "/no/such/program"])
    assert rc == 75
    assert "/no/such/program" in json.load(open(status))["infra"]


def test_the_trial_goes_when_its_parent_dies(tmp_path):
    """A Ray worker killed under a trial (Ctrl-C's force-cancel, a lost node): PR_SET_PDEATHSIG."""
    token = uuid.uuid4().hex
    pidfile = str(tmp_path / "pid")
    middle = ("import os, subprocess, sys, time\n"
              "subprocess.Popen([sys.executable, '-m', 'modrob_sweep.reaper', '--token', %r, '--parent', "
              "str(os.getpid()), '--status', %r, '--', sys.executable, '-c', %r, %r])\n"
              "time.sleep(300)\n" % (token, str(tmp_path / "status.json"), HANG, pidfile))
    worker = subprocess.Popen([sys.executable, "-c", middle], start_new_session=True)
    grandchild = int(wait_file(pidfile))
    assert alive(grandchild)
    worker.kill()
    worker.wait()
    deadline = time.monotonic() + 20
    while with_token(token) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert with_token(token) == [] and not alive(grandchild)


def test_render_gives_the_trial_its_own_display_and_stops_it(tmp_path):
    """render: true -> an Xvfb on a free display for the command, gone when the trial ends."""
    token = uuid.uuid4().hex
    status = str(tmp_path / "status.json")
    probe = ("import os, subprocess, sys\n"
             "d = os.environ['DISPLAY']\n"
             "ok = subprocess.call(['xdpyinfo', '-display', d], stdout=subprocess.DEVNULL) == 0 if "
             "os.path.exists('/usr/bin/xdpyinfo') else os.path.exists('/tmp/.X11-unix/X' + d[1:])\n"
             "open(sys.argv[1], 'w').write('%s %s' % (d, ok))\n")
    out = str(tmp_path / "display")
    rc = subprocess.call([sys.executable, "-m", "modrob_sweep.reaper", "--token", token, "--parent",
                          str(os.getpid()),
                          "--status", status, "--xvfb", "--", sys.executable, "-c", probe, out], timeout=60)
    assert rc == 0, open(status).read()
    display, ok = open(out).read().split()
    assert display.startswith(":") and ok == "True"
    assert json.load(open(status))["leftovers"] == []      # its own Xvfb is not a leftover of the scenario
    assert with_token(token) == []
