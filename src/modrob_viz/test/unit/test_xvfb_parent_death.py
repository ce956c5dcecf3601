"""A private Xvfb ends with the process that started it, even when that process is killed."""
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

from modrob_sim.procs import alive

pytestmark = pytest.mark.skipif(shutil.which("Xvfb") is None or shutil.which("setpriv") is None,
                                reason="needs Xvfb and setpriv")


def test_xvfb_ends_when_its_starter_is_killed():
    code = ("import sys, time\n"
            "from modrob_viz.render.xvfb import Xvfb\n"
            "x = Xvfb(64, 64)\n"
            "print(x.proc.pid, flush=True)\n"
            "time.sleep(60)\n")
    starter = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    xvfb_pid = int(starter.stdout.readline())
    try:
        assert alive(xvfb_pid)
        starter.send_signal(signal.SIGKILL)      # no stop(): as a crash
        starter.wait()
        deadline = time.monotonic() + 10
        while alive(xvfb_pid) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not alive(xvfb_pid), "Xvfb %d outlived the process that started it" % xvfb_pid
    finally:
        if alive(xvfb_pid):
            os.kill(xvfb_pid, signal.SIGKILL)
        if starter.poll() is None:
            starter.kill()
