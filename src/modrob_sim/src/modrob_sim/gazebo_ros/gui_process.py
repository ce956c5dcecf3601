"""RViz as gzclient's child process (pure: no rospy; gzclient is not a ROS node, RViz is).

gzclient starts RViz and stays its parent instead of exec'ing it, for two reasons:

- RViz under a software-rendered X server (Xvfb, Mesa) sometimes crashes while it shuts down
  (SIGABRT or SIGSEGV from its OpenGL teardown). When that happens after gzclient was asked to
  stop, the GUI was being closed anyway: gzclient says so in one line and exits 0, so roslaunch
  reports a clean stop. A crash or an error exit BEFORE any stop request is a real failure and
  stays one: gzclient says so and exits non-zero (128 + the signal's number for a signal, as a
  shell reports it), and roslaunch prints its "process has died" line.
- RViz under such a display also crashes now and then while it STARTS (heap corruption reported
  by glibc and an abort, about 1 start in 100 here). A crash by a signal within ``EARLY`` seconds
  of the start, before any stop request, is said in one line and RViz is started once more (as
  roslaunch's ``respawn`` would, once); a second such crash, or one later on, is a failure.
- Whoever holds the X connection matters: a bare X server (Xvfb without ``-noreset``) resets when
  its last client leaves, and a client that connects during the reset fails (Qt: "could not
  connect to display", an abort). gzclient's display check is such a client; it keeps that
  connection (``keep``) open until RViz has ended, so RViz never connects into a reset.

Signals. roslaunch stops a node by SIGINT to the node's process group, then SIGTERM after
``sigint_timeout`` (15 s), then SIGKILL after ``sigterm_timeout`` (2 s) (roslaunch/nodeprocess.py).
RViz runs in a process group of its own, so a group signal to gzclient does not reach it;
gzclient forwards each SIGINT or SIGTERM it receives to RViz once. A SIGKILL to gzclient cannot
be forwarded: RViz has the kernel's parent-death signal (prctl PR_SET_PDEATHSIG, SIGKILL) set
before it starts, so it ends with gzclient whatever ends gzclient; an exit path of gzclient's own
that killed RViz's group would not run on SIGKILL. (The parent-death signal belongs to the thread
that started the child: ``run`` must be called from the main thread, the one that lives as long
as the process. gzclient has no other threads, which ``preexec_fn`` also needs.)
"""
import ctypes
import os
import signal
import subprocess
import time

PR_SET_PDEATHSIG = 1   # <linux/prctl.h>
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
KNOWN_CRASH = "a known RViz/Mesa crash at exit"
#: seconds after its start within which a crash of the child is taken for a start-up crash
EARLY = 10.0


def signal_name(number):
    try:
        return signal.Signals(number).name
    except ValueError:
        return "signal %d" % number


def outcome(returncode, stop_signals, name="rviz"):
    """What gzclient reports when its child ended with ``returncode`` (Popen's: negative for a
    signal) after the stop signals ``stop_signals`` (those gzclient received and forwarded, in
    order; empty: nobody asked it to stop). Returns ``(exit_code, line or None)``."""
    if returncode == 0:
        return 0, None
    if stop_signals:
        if returncode < 0 and -returncode in stop_signals:
            return 0, None   # ended by the signal it was sent: an ordinary stop
        how = signal_name(-returncode) if returncode < 0 else "exit status %d" % returncode
        why = " (%s)" % KNOWN_CRASH if returncode < 0 else ""
        return 0, "%s ended with %s while stopping%s; ignored" % (name, how, why)
    if returncode < 0:
        return 128 - returncode, ("%s died of %s before any stop request: the GUI failed (its output "
                                  "above says why)" % (name, signal_name(-returncode)))
    return returncode, "%s exited with status %d before any stop request: the GUI failed" % (name, returncode)


def _die_with_parent(parent):
    """preexec_fn: the child's own process group and SIGKILL when ``parent`` dies."""
    libc = ctypes.CDLL(None, use_errno=True)   # loaded here, before the fork

    def preexec():
        os.setpgid(0, 0)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if os.getppid() != parent:   # the parent died before the death signal was set
            os._exit(1)
    return preexec


class ChildRunner(object):
    """Runs ``argv`` as a child, forwards SIGINT/SIGTERM to it once each, waits for it and turns
    its end into gzclient's exit code (``outcome``). ``log(line)`` prints gzclient's one line."""

    def __init__(self, argv, log, name="rviz"):
        self.argv, self.log, self.name = list(argv), log, name
        self.child = None
        self.received = []     # stop signals, in order
        self.forwarded = 0     # how many of them the child has been sent

    def _on_signal(self, signum, frame):
        self.received.append(signum)
        self._forward()

    def _forward(self):
        # called from the handler and after Popen returns: a signal that came while the child was
        # being started is sent once it exists
        while self.child is not None and self.forwarded < len(self.received):
            sig = self.received[self.forwarded]
            self.forwarded += 1
            if self.child.returncode is None:
                try:
                    self.child.send_signal(sig)
                except ProcessLookupError:
                    pass

    def run(self):
        previous = {s: signal.signal(s, self._on_signal) for s in STOP_SIGNALS}
        try:
            if self.received:   # asked to stop before the GUI started: do not start it
                return 0
            restarts = 1
            while True:
                started = time.monotonic()
                try:
                    self.child = subprocess.Popen(self.argv, preexec_fn=_die_with_parent(os.getpid()))
                except OSError as exc:
                    self.log("cannot start %s (%s): is it installed (Debian package rviz)?"
                             % (self.argv[0], exc.strerror or exc))
                    return 127
                self._forward()
                returncode = self.child.wait()   # retried after each signal handler (PEP 475)
                after = time.monotonic() - started
                if returncode >= 0 or self.received or after > EARLY or not restarts:
                    break
                restarts -= 1
                self.log("%s died of %s %.1f s after it started, before any stop request (a known "
                         "crash of RViz at start on a software-rendered display); starting it once more"
                         % (self.name, signal_name(-returncode), after))
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)
        code, line = outcome(returncode, self.received, self.name)
        if line:
            self.log(line)
        return code


def run(argv, log=print, keep=None, name="rviz"):
    """``ChildRunner(argv, log).run()`` with ``keep`` (an open display connection, or None) closed
    only after the child has ended. Returns gzclient's exit code."""
    try:
        return ChildRunner(argv, log, name).run()
    finally:
        if keep is not None:
            keep.close()
