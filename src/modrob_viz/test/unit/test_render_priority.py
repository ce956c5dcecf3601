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


def test_cpus_auto_leaves_the_first_cpu_to_the_rest():
    # the node's default is "all"; "auto" is asked for by launch argument
    assert priority.check_cpus("auto", [0, 1]) == [1]
    assert priority.check_cpus("auto", [0, 1, 2, 3]) == [1, 2, 3]
    assert priority.check_cpus("auto", [2, 5]) == [5]
    assert priority.check_cpus("auto", [0]) is None         # one CPU: nothing to leave
    assert priority.check_cpus(" AUTO ", [0, 1]) == [1]


def test_cpus_all_and_lists():
    assert priority.check_cpus("all", [0, 1]) is None
    assert priority.check_cpus("", [0, 1]) is None
    assert priority.check_cpus(1, [0, 1]) == [1]              # `_cpus:=1` arrives as an int
    assert priority.check_cpus("0-2,5", range(8)) == [0, 1, 2, 5]
    assert priority.check_cpus("3,1", range(4)) == [1, 3]


@pytest.mark.parametrize("value", ["x", "1-", "-1", "2-1", "1,,2", None, True, 1.5, [1]])
def test_bad_cpus_are_refused_by_name(value):
    with pytest.raises(ConfigError, match=r"~cpus must be 'auto', 'all' or a CPU list"):
        priority.check_cpus(value, [0, 1])


def test_cpus_the_process_may_not_use_are_refused():
    with pytest.raises(ConfigError,
                       match=r"~cpus '1-3': CPU 2,3 not available to this process \(it may use 0,1\)"):
        priority.check_cpus("1-3", [0, 1])


def test_render_threads_follow_the_cpu_set_unless_given():
    assert priority.threads_for(-1, [1]) == 1
    assert priority.threads_for(-1, [1, 2, 3]) == 3
    assert priority.threads_for(-1, None) == -1            # not confined: Mesa's default
    assert priority.threads_for(0, [1]) == 0
    assert priority.threads_for(4, [1]) == 4


def test_every_thread_and_what_starts_later_is_confined():
    cpus = sorted(os.sched_getaffinity(0))
    one = cpus[-1]
    code = textwrap.dedent("""
        import os, subprocess, threading
        from modrob_viz.render import priority
        ev = threading.Event()
        t = threading.Thread(target=ev.wait, daemon=True)
        t.start()
        n = priority.confine([%d])
        sets = set(tuple(sorted(os.sched_getaffinity(int(tid)))) for tid in os.listdir("/proc/self/task"))
        child = subprocess.run(["sh", "-c", "grep Cpus_allowed_list /proc/self/status"],
                               stdout=subprocess.PIPE, text=True).stdout.split()[-1]
        ev.set()
        print(n, sorted(sets), child)
    """ % one)
    out = subprocess.run([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=dict(os.environ), check=True).stdout.split(None, 1)
    assert int(out[0]) >= 2
    assert out[1].split()[:-1] == ["[(%d,)]" % one]
    assert out[1].split()[-1] == str(one)                  # a process started afterwards inherits it
