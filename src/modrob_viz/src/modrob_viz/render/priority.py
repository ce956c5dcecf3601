"""The renderer's share of the CPU: its scheduling priority and Mesa's rasterizer threads.

On a machine with few cores the renderer (Qt/RViz thread, Mesa's llvmpipe threads, its Xvfb)
competes with the simulator for the CPU. ``lower_priority`` nices every thread of this process,
and so everything it starts afterwards (Xvfb, llvmpipe's threads inherit it): when both want the
CPU the simulator gets it first, and the renderer still uses what is idle.
``set_render_threads`` sets Mesa llvmpipe's rasterizer threads (LP_NUM_THREADS; Mesa's default is
one per CPU, 0 rasterizes in the thread that renders).
``confine`` keeps every thread of this process, and so its Xvfb and Mesa's threads started
afterwards, on a set of CPUs (``~cpus``; "auto": all but one of the CPUs this process may use, so
that on a 2-core machine a simulator running flat out keeps a core whatever the renderer draws).
The default leaves the renderer on every CPU: confined, it draws slower whenever the CPUs are
shared with other work.
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


def available_cpus():
    """The CPUs this process may run on (its affinity mask), sorted."""
    return sorted(os.sched_getaffinity(0))


def _cpu_list(text):
    """Linux CPU list syntax ("1", "0-3", "1,3,5-7") -> set of ints; ValueError when malformed."""
    out = set()
    for part in text.split(","):
        part = part.strip()
        lo, sep, hi = part.partition("-")
        lo, hi = int(lo), int(hi) if sep else int(lo)
        if lo < 0 or hi < lo:
            raise ValueError(part)
        out.update(range(lo, hi + 1))
    return out


def check_cpus(value, available=None):
    """``~cpus`` -> sorted list of CPU numbers to confine the renderer to, or None (no confinement).

    "all" (the node's default) or "": no confinement. "auto": every CPU this process may use but the
    first, when it may use two or more (the simulator and the rest keep that one); None on one CPU.
    Else a CPU list as Linux writes them ("1", "2-3", "1,3"), each CPU one this process may use."""
    available = available_cpus() if available is None else sorted(available)
    if isinstance(value, bool) or value is None:
        raise ConfigError("~cpus must be 'auto', 'all' or a CPU list such as '1' or '1-3', got %r" % (value,))
    if isinstance(value, int):
        value = str(value)
    if not isinstance(value, str):
        raise ConfigError("~cpus must be 'auto', 'all' or a CPU list such as '1' or '1-3', got %r" % (value,))
    text = value.strip().lower()
    if text == "auto":
        return available[1:] if len(available) >= 2 else None
    if text in ("all", ""):
        return None
    try:
        cpus = _cpu_list(text)
    except ValueError:
        raise ConfigError("~cpus must be 'auto', 'all' or a CPU list such as '1' or '1-3', got %r" % (value,))
    missing = sorted(cpus - set(available))
    if missing:
        raise ConfigError("~cpus %r: CPU %s not available to this process (it may use %s)"
                          % (value, ",".join(str(c) for c in missing), ",".join(str(c) for c in available)))
    return sorted(cpus)


def confine(cpus):
    """Every thread of this process on ``cpus`` (a list, or None: leave it); threads and processes
    started later inherit it. Returns the number of threads changed."""
    if not cpus:
        return 0
    changed = 0
    for tid in os.listdir("/proc/self/task"):
        try:
            os.sched_setaffinity(int(tid), cpus)
            changed += 1
        except (OSError, ValueError):     # the thread ended meanwhile
            continue
    return changed


def threads_for(render_threads, cpus):
    """LP_NUM_THREADS to use: ``render_threads`` when given (>= 0); with Mesa's default (-1) and the
    renderer confined to ``cpus``, one rasterizer thread per CPU of the set (Mesa would start one
    per CPU of the machine); else -1 (Mesa's default)."""
    if render_threads >= 0 or not cpus:
        return render_threads
    return len(cpus)


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
