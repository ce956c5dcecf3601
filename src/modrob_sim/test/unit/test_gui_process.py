"""Tier 1: gzclient runs RViz as its child (modrob_sim.gazebo_ros.gui_process).

The real gzclient script, stopped as roslaunch stops a node (signals to its process group), with
stand-ins for RViz: small Python programs found as ``rviz`` on PATH that print a line when they are
ready and then crash or exit as RViz might. The display check is satisfied by a listening TCP
socket (DISPLAY=127.0.0.1:N) instead of an X server.
"""
import os
import random
import re
import select
import signal
import socket
import subprocess
import sys
import time

import pytest

from modrob_sim.gazebo_ros.gui_process import KNOWN_CRASH, outcome
from modrob_sim.procs import alive, proc_stat

GZCLIENT = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                        "scripts", "gzclient")

HEAD = "import os, signal, sys\n"
READY = "print('ready', os.getpid(), ' '.join(sys.argv[1:]), flush=True)\n"   # after its handlers
WAIT = "while True: signal.pause()\n"
ABORT_ON_SIGINT = HEAD + "signal.signal(signal.SIGINT, lambda *a: os.abort())\n" + READY + WAIT
EXIT_0_ON_SIGINT = HEAD + "signal.signal(signal.SIGINT, lambda *a: os._exit(0))\n" + READY + WAIT
CRASH_AT_ONCE = HEAD + READY + "os.abort()\n"
# crashes at its first start only (a file beside it remembers), then runs until SIGINT
CRASH_AT_FIRST_START = HEAD + ("mark = os.path.join(os.path.dirname(sys.argv[0]), 'started')\n"
                               "first = not os.path.exists(mark)\n"
                               "open(mark, 'a').close()\n"
                               "signal.signal(signal.SIGINT, lambda *a: os._exit(0))\n") + READY + \
    "if first: os.abort()\n" + WAIT
FAIL_AT_ONCE = HEAD + READY + "sys.exit(3)\n"
IGNORE_SIGINT = HEAD + ("def ignored(*a):\n"
                        "    print('SIGINT ignored', flush=True)\n"
                        "signal.signal(signal.SIGINT, ignored)\n") + READY + WAIT


# ---- the rule ----------------------------------------------------------------------------------
def test_outcome_of_each_ending():
    assert outcome(0, []) == (0, None)
    assert outcome(0, [signal.SIGINT]) == (0, None)
    assert outcome(-signal.SIGINT, [signal.SIGINT]) == (0, None)          # stopped by its signal
    assert outcome(-signal.SIGTERM, [signal.SIGINT, signal.SIGTERM]) == (0, None)
    code, line = outcome(-signal.SIGABRT, [signal.SIGINT])
    assert code == 0 and line == "rviz ended with SIGABRT while stopping (%s); ignored" % KNOWN_CRASH
    code, line = outcome(1, [signal.SIGINT])
    assert code == 0 and line == "rviz ended with exit status 1 while stopping; ignored"
    code, line = outcome(-signal.SIGSEGV, [])
    assert code == 128 + signal.SIGSEGV and "SIGSEGV before any stop request" in line
    code, line = outcome(2, [])
    assert code == 2 and "status 2 before any stop request" in line
    code, line = outcome(-signal.SIGINT, [])                               # someone else's signal
    assert code == 128 + signal.SIGINT and "SIGINT before any stop request" in line


# ---- the real gzclient with stand-ins for RViz ----------------------------------------------------
def fake_display():
    """A listening TCP socket on 127.0.0.1:6000+N (what the display check connects to)."""
    for n in random.sample(range(100, 900), 800):
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        try:
            s.bind(("127.0.0.1", 6000 + n))
        except OSError:
            s.close()
            continue
        s.listen(8)
        return s, "127.0.0.1:%d" % n
    raise RuntimeError("no free port in 6100..6899 for a stand-in display")


class Gzclient(object):
    """gzclient started as roslaunch starts a node (its own session), with ``child`` as rviz
    (None: no rviz on PATH)."""

    def __init__(self, tmp_path, child):
        bin_dir = tmp_path / "bin"
        bin_dir.mkdir()
        path = str(bin_dir)
        if child is not None:
            rviz = bin_dir / "rviz"
            rviz.write_text("#!%s\n%s" % (sys.executable, child))
            rviz.chmod(0o755)
            path += ":" + os.environ["PATH"]
        self.server, display = fake_display()
        env = dict(os.environ, DISPLAY=display, PATH=path)
        self.proc = subprocess.Popen([sys.executable, GZCLIENT, "--rviz-config", "x.rviz",
                                      "__name:=gazebo_gui"], env=env, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, start_new_session=True)
        self.out = b""

    def _read(self, end):
        """One chunk of output into ``self.out``, waiting until wall time ``end``; False at EOF."""
        left = end - time.monotonic()
        assert left > 0 and select.select([self.proc.stdout], [], [], left)[0], \
            "gzclient's output stalled; so far:\n%s" % self.out.decode(errors="replace")
        chunk = os.read(self.proc.stdout.fileno(), 4096)
        self.out += chunk
        return bool(chunk)

    def read_until(self, pattern, timeout=30.0):
        """The first match of ``pattern`` (regex) in the output, reading it as it comes."""
        end = time.monotonic() + timeout
        while not re.search(pattern, self.out.decode(errors="replace")):
            assert self._read(end), "no %r before the output ended:\n%s" % (pattern, self.out.decode())
        return re.search(pattern, self.out.decode(errors="replace"))

    def read_to_end(self, timeout=30.0):
        """The whole output: EOF once every process holding the pipe (gzclient, the stand-in) has
        ended."""
        end = time.monotonic() + timeout
        while self._read(end):
            pass
        return self.out.decode(errors="replace")

    def ready(self):
        """The stand-in's pid once it has started (and its handlers are set)."""
        return int(self.read_until(r"ready (\d+).*\n").group(1))

    def stop(self, sig=signal.SIGINT):
        os.killpg(self.proc.pid, sig)      # as roslaunch does

    def wait(self, timeout=30.0):
        """gzclient's exit code and output, once it and the stand-in have ended."""
        code = self.proc.wait(timeout)
        return code, self.read_to_end(timeout)

    def close(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        self.proc.stdout.close()
        self.server.close()


@pytest.fixture
def gzclient(tmp_path):
    made = []

    def make(child):
        made.append(Gzclient(tmp_path, child))
        return made[-1]
    yield make
    for g in made:
        g.close()


def pgid_of(pid):
    return proc_stat(pid)[3]


def test_a_crash_while_stopping_is_one_plain_line_and_a_clean_exit(gzclient):
    g = gzclient(ABORT_ON_SIGINT)
    child = g.ready()
    assert "-d x.rviz __name:=gazebo_gui" in g.out.decode()        # the config and the remappings
    # RViz has a process group of its own: roslaunch's group signal reaches it only through
    # gzclient, once
    assert pgid_of(child) != pgid_of(g.proc.pid) == g.proc.pid
    g.stop()
    code, out = g.wait()
    assert code == 0, out
    lines = [x for x in out.splitlines() if x.startswith("gzclient:")]
    assert lines == ["gzclient: rviz ended with SIGABRT while stopping (%s); ignored" % KNOWN_CRASH]


def test_a_clean_stop_says_nothing(gzclient):
    g = gzclient(EXIT_0_ON_SIGINT)
    g.ready()
    g.stop()
    code, out = g.wait()
    assert code == 0 and "gzclient:" not in out, out


def test_sigterm_after_an_unanswered_sigint_is_forwarded_too(gzclient):
    # roslaunch escalates to SIGTERM when SIGINT did not end the node within its timeout
    g = gzclient(IGNORE_SIGINT)
    g.ready()
    g.stop(signal.SIGINT)
    g.read_until("SIGINT ignored")
    g.stop(signal.SIGTERM)
    code, out = g.wait()
    assert code == 0 and "gzclient:" not in out, out


@pytest.mark.parametrize("child, code, words", [
    (CRASH_AT_ONCE, 128 + signal.SIGABRT, "rviz died of SIGABRT before any stop request"),
    (FAIL_AT_ONCE, 3, "rviz exited with status 3 before any stop request"),
], ids=["crash", "error_exit"])
def test_an_end_before_any_stop_request_fails_loudly(gzclient, child, code, words):
    # a crash at start is tried once more (below); a second one fails
    g = gzclient(child)
    got, out = g.wait()
    assert got == code, out
    assert "gzclient: " + words in out
    assert out.count("ready ") == (2 if child == CRASH_AT_ONCE else 1), out


def test_a_crash_at_start_is_said_and_rviz_started_once_more(gzclient):
    g = gzclient(CRASH_AT_FIRST_START)
    first = g.ready()
    g.read_until(r"gzclient: rviz died of SIGABRT [0-9.]+ s after it started, before any stop request "
                 r"\(a known crash of RViz at start on a software-rendered display\); starting it once more")
    g.out = g.out[g.out.index(b"starting it once more"):]
    second = g.ready()
    assert second != first and alive(second)
    g.stop()
    code, out = g.wait()
    assert code == 0 and out.count("gzclient:") == 0, out


def test_rviz_ends_with_a_killed_gzclient(gzclient):
    # SIGKILL (roslaunch's last resort) cannot be forwarded: the parent-death signal ends RViz
    g = gzclient(IGNORE_SIGINT)
    child = g.ready()
    g.stop(signal.SIGKILL)
    g.proc.wait(10)
    g.read_to_end(10)       # EOF: the stand-in, which holds the output pipe too, is ending as well
    end = time.monotonic() + 10   # ... and a moment later no longer running (a zombie or gone)
    while alive(child) and time.monotonic() < end:
        time.sleep(0.01)
    assert not alive(child), "rviz %d outlived gzclient" % child


def test_no_rviz_to_start_is_said_by_name(gzclient):
    code, out = gzclient(None).wait()
    assert code == 127 and "gzclient: cannot start rviz" in out and "Debian package rviz" in out, out
