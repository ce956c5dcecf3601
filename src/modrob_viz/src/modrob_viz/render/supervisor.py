"""camera_renderer runs as a child of a small watcher that starts it again when it dies of a crash
signal: about one start in 15-30 under heavy load dies inside Mesa's software rasterizer while the
camera panels are first shown (docs/cameras.md, "Pixels"), and a simulation should not lose its
cameras for that. Each restart is said on stderr; a renderer that ends any other way (a
configuration error, Ctrl-C, roslaunch's SIGINT/SIGTERM, which the watcher passes on) is not
restarted, and the watcher exits with its code. ``MODROB_RENDERER_RESTARTS`` (default 3) bounds the
restarts; 0 runs the renderer without the watcher's help (it still runs as a child).

The watcher does no ROS work (the child is the node, with the same name and arguments); the child
gets SIGTERM when the watcher is killed (``setpriv --pdeathsig``), so nothing is left behind."""
import os
import signal
import subprocess
import sys

from modrob_viz.render.xvfb import _parent_death

CHILD_ENV = "MODROB_RENDERER_CHILD"
RESTARTS_ENV = "MODROB_RENDERER_RESTARTS"
CRASH_SIGNALS = {signal.SIGSEGV: "SIGSEGV", signal.SIGABRT: "SIGABRT", signal.SIGBUS: "SIGBUS"}


def is_child(env=None):
    return (env if env is not None else os.environ).get(CHILD_ENV) == "1"


def restarts_allowed(env=None):
    """MODROB_RENDERER_RESTARTS as a count >= 0 (3 when unset); ValueError naming it otherwise."""
    raw = (env if env is not None else os.environ).get(RESTARTS_ENV, "3")
    try:
        n = int(raw)
    except ValueError:
        n = -1
    if n < 0:
        raise ValueError("%s=%r: give a whole number of restarts >= 0 (default 3)" % (RESTARTS_ENV, raw))
    return n


def supervise(argv, env=None, restarts=3, log=None, name="camera_renderer"):
    """Run ``argv`` as a child with CHILD_ENV=1 until it ends other than by a crash signal, or it
    crashed ``restarts`` times more; returns the exit code to leave with (128 + signal for a
    signal)."""
    log = log or (lambda text: print(text, file=sys.stderr, flush=True))
    child_env = dict(os.environ if env is None else env)
    child_env[CHILD_ENV] = "1"
    state = {"child": None, "stopping": False}

    def forward(num, _frame):
        state["stopping"] = True
        child = state["child"]
        if child is not None and child.poll() is None:
            child.send_signal(num)

    old = {sig: signal.signal(sig, forward) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        crashes = 0
        while True:
            state["child"] = subprocess.Popen(_parent_death() + list(argv), env=child_env)
            if state["stopping"]:           # a signal came while it was being started
                state["child"].send_signal(signal.SIGTERM)
            code = state["child"].wait()
            sig = -code if code < 0 else None
            if state["stopping"] or sig not in CRASH_SIGNALS or crashes >= restarts:
                if sig in CRASH_SIGNALS and crashes >= restarts and not state["stopping"]:
                    log("%s: the renderer died of %s again; %d restart(s) used up (%s), giving up"
                        % (name, CRASH_SIGNALS[sig], restarts, RESTARTS_ENV))
                return 128 + sig if sig is not None else code
            crashes += 1
            log("%s: the renderer died of %s (a known fault in Mesa's software rasterizer while camera "
                "panels are first shown, docs/cameras.md); starting it again (restart %d of %d)"
                % (name, CRASH_SIGNALS[sig], crashes, restarts))
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
