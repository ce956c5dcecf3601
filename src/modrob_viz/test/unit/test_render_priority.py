"""The renderer's scheduling priority and llvmpipe thread count (modrob_viz.render.priority)."""
import os
import subprocess
import sys
import textwrap

import pytest

from modrob_viz.errors import ConfigError
from modrob_viz.render import priority


def test_nice_and_threads_accept_integers():
    assert priority.check_nice(10) == 10
    assert priority.check_nice("0") == 0
    assert priority.check_nice(19.0) == 19
    assert priority.check_threads(0) == 0
    assert priority.check_threads(-1) == -1
    assert priority.check_threads(3) == 3


@pytest.mark.parametrize("value", [-1, 20, 2.5, "ten", None, True, [1]])
def test_bad_nice_is_refused_by_name(value):
    with pytest.raises(ConfigError, match=r"~nice must be an integer in 0\.\.19"):
        priority.check_nice(value)


@pytest.mark.parametrize("value", [-2, 1.5, "x", None, False])
def test_bad_threads_are_refused_by_name(value):
    with pytest.raises(ConfigError, match=r"~render_threads must be an integer >= -1"):
        priority.check_threads(value)


def test_render_threads_set_lp_num_threads_unless_mesa_default():
    env = {}
    assert priority.set_render_threads(-1, env) is None and env == {}
    assert priority.set_render_threads(0, env) == "0" and env["LP_NUM_THREADS"] == "0"
    assert priority.set_render_threads(2, env) == "2" and env["LP_NUM_THREADS"] == "2"


def test_every_thread_and_what_starts_later_is_niced():
    # in a child process: the niceness cannot be raised back in this one
    code = textwrap.dedent("""
        import os, subprocess, threading
        from modrob_viz.render import priority
        ev = threading.Event()
        t = threading.Thread(target=ev.wait, daemon=True)
        t.start()
        base = os.getpriority(os.PRIO_PROCESS, 0)
        n = priority.lower_priority(5)
        nices = [os.getpriority(os.PRIO_PROCESS, int(tid)) - base for tid in os.listdir("/proc/self/task")]
        child = subprocess.run(["sh", "-c", "cat /proc/self/stat"], stdout=subprocess.PIPE, text=True).stdout
        child_nice = int(child.rsplit(")", 1)[1].split()[16]) - base
        ev.set()
        print(n, sorted(set(nices)), child_nice)
    """)
    out = subprocess.run([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=dict(os.environ), check=True).stdout.split()
    base = os.getpriority(os.PRIO_PROCESS, 0)
    expect = min(19, base + 5) - base
    assert int(out[0]) >= 2                       # the main thread and the waiting one
    assert out[1:-1] == ["[%d]" % expect]
    assert int(out[-1]) == expect                 # a process started afterwards inherits it
