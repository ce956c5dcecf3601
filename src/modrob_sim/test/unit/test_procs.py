"""Tier 1: modrob_sim.procs reads a process's state, parent and group from /proc."""
import os
import subprocess
import sys
import time

from modrob_sim.procs import alive, proc_stat, start_time


def test_proc_stat_and_alive_follow_a_process_to_its_end():
    p = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"], start_new_session=True)
    try:
        name, state, ppid, pgrp = proc_stat(p.pid)
        assert ppid == os.getpid() and pgrp == p.pid and state != "Z" and alive(p.pid)
        # later than this process, and the same at each look
        assert start_time(p.pid) >= start_time(os.getpid()) and start_time(p.pid) == start_time(p.pid)
    finally:
        p.kill()
    end = time.monotonic() + 10
    while proc_stat(p.pid)[1] != "Z" and time.monotonic() < end:   # ended, not yet waited for
        time.sleep(0.01)
    assert proc_stat(p.pid)[1] == "Z" and not alive(p.pid) and start_time(p.pid) is None
    p.wait()
    assert proc_stat(p.pid) is None and not alive(p.pid) and start_time(p.pid) is None
