"""The renderer's share of the CPU: its scheduling priority and Mesa's rasterizer threads.

On a machine with few cores the renderer (Qt/RViz thread, Mesa's llvmpipe threads, its Xvfb)
competes with the simulator for the CPU. ``lower_priority`` nices every thread of this process,
and so everything it starts afterwards (Xvfb, llvmpipe's threads inherit it): when both want the
CPU the simulator gets it first, and the renderer still uses what is idle.
``set_render_threads`` sets Mesa llvmpipe's rasterizer threads (LP_NUM_THREADS; Mesa's default is
one per CPU, 0 rasterizes in the thread that renders).
"""
import os

from modrob_viz.errors import ConfigError

MAX_NICE = 19


def _integer(name, value, low, high=None):
    """``value`` (int, integral float or digits) as an int in low..high, or ConfigError naming ``name``."""
    bad = ConfigError("%s must be an integer %s, got %r"
                      % (name, ">= %d" % low if high is None else "in %d..%d" % (low, high), value))
    if isinstance(value, bool):
        raise bad
    try:
        n = int(value)
    except (TypeError, ValueError):
        raise bad
    if isinstance(value, float) and value != n or n < low or high is not None and n > high:
        raise bad
    return n


def check_nice(value):
    return _integer("~nice", value, 0, MAX_NICE)


def check_threads(value):
    """-1: Mesa's default (one rasterizer thread per CPU); 0: none (the calling thread rasterizes)."""
    return _integer("~render_threads", value, -1)


def lower_priority(nice):
    """Every thread of this process ``nice`` steps lower (capped at 19); threads and processes
    started later inherit it. Returns the number of threads changed."""
    if nice <= 0:
        return 0
    changed = 0
    for tid in os.listdir("/proc/self/task"):
        try:
            now = os.getpriority(os.PRIO_PROCESS, int(tid))
            os.setpriority(os.PRIO_PROCESS, int(tid), min(MAX_NICE, now + nice))
            changed += 1
        except (OSError, ValueError):     # the thread ended meanwhile
            continue
    return changed


def set_render_threads(threads, environ=None):
    """Mesa's llvmpipe rasterizer threads (LP_NUM_THREADS), before the first OpenGL context: 0 = no
    rasterizer threads (each render is rasterized in the thread that flushes it), -1 leaves Mesa's
    default. Returns the value set, or None."""
    environ = os.environ if environ is None else environ
    if threads < 0:
        return None
    environ["LP_NUM_THREADS"] = str(threads)
    return environ["LP_NUM_THREADS"]
