"""Start Xvfb on a free display for a test that opens windows, and stop it afterwards."""
import os
import random
import subprocess
import time


class Xvfb(object):
    def __init__(self, size="1280x1024x24"):
        self.size = size
        self.proc = None
        self.display = None

    def __enter__(self):
        for _ in range(50):
            n = random.randint(100, 899)
            if not os.path.exists("/tmp/.X11-unix/X%d" % n) and not os.path.exists("/tmp/.X%d-lock" % n):
                break
        else:
            raise RuntimeError("no free X display number in 100..899")
        self.proc = subprocess.Popen(["Xvfb", ":%d" % n, "-screen", "0", self.size, "-nolisten", "tcp"],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 20
        while not os.path.exists("/tmp/.X11-unix/X%d" % n):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError("Xvfb :%d did not start" % n)
            time.sleep(0.05)
        self.display = ":%d" % n
        os.environ["DISPLAY"] = self.display
        os.environ.pop("QT_QPA_PLATFORM", None)
        return self

    def __exit__(self, *exc):
        if self.proc is not None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
