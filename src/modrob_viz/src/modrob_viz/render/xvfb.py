"""A private X server for off-screen OpenGL (Mesa llvmpipe) when there is no display."""
import os
import random
import shutil
import subprocess
import time

from modrob_viz.errors import ConfigError


def free_display(rng=None):
    """A display number in 100..899 with no X socket or lock file."""
    rng = rng or random.Random()
    for n in rng.sample(range(100, 900), 800):
        if not os.path.exists("/tmp/.X11-unix/X%d" % n) and not os.path.exists("/tmp/.X%d-lock" % n):
            return n
    raise ConfigError("no free X display number in 100..899 (stale /tmp/.X*-lock files?)")


def _parent_death():
    """``setpriv --pdeathsig TERM`` (util-linux) before a command when available, else nothing."""
    return ["setpriv", "--pdeathsig", "TERM"] if shutil.which("setpriv") else []


class Xvfb(object):
    """``Xvfb :N -screen 0 WxHx24`` started on a free N; ``stop()`` ends it. ``display`` is ":N".
    It also ends when the thread that started it does (a renderer that crashed or was killed):
    start it from the thread that lives as long as it is needed."""

    def __init__(self, width=4096, height=2304, timeout=15.0):
        if shutil.which("Xvfb") is None:
            raise ConfigError("no DISPLAY and no Xvfb: install the Debian package xvfb "
                              "(scripts/debian-packages.txt) or run with a display")
        last = None
        for _attempt in range(3):
            n = free_display()
            # own session: roslaunch's SIGINT must not end it first; SIGTERM when this process dies
            # without stopping it (a crash or SIGKILL left one Xvfb per renderer behind)
            proc = subprocess.Popen(_parent_death() + ["Xvfb", ":%d" % n, "-screen", "0",
                                                       "%dx%dx24" % (width, height), "-nolisten", "tcp"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                    start_new_session=True)
            deadline = time.monotonic() + timeout
            while time.monotonic() < deadline and proc.poll() is None:
                if os.path.exists("/tmp/.X11-unix/X%d" % n):
                    self.proc, self.number, self.display = proc, n, ":%d" % n
                    return
                time.sleep(0.05)
            last = proc.poll()
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        raise ConfigError("Xvfb did not start (exit code %r) on three display numbers" % (last,))

    def __enter__(self):
        """As a context manager (tests that open windows): $DISPLAY points here until exit."""
        os.environ["DISPLAY"] = self.display
        os.environ.pop("QT_QPA_PLATFORM", None)
        return self

    def __exit__(self, *exc):
        self.stop()

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


def ensure_display(width=4096, height=2304, display=""):
    """Point $DISPLAY where the renderer draws. ``display`` empty (the default): a private Xvfb of
    that size, returned for the caller to stop, whatever $DISPLAY the user has: the renderer's
    panels are its image buffers, never windows on the user's desktop (they covered RViz there).
    ``display`` an X display (":0"): draw there and return None (to watch the renderer work)."""
    if display:
        os.environ["DISPLAY"] = display
        return None
    x = Xvfb(width, height)
    os.environ["DISPLAY"] = x.display
    return x
