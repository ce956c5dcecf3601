"""A scenario's ``roslaunch`` as a runner script starts it (``make demo``, the sweeps' trials):
on its own ROS master at a free port, in its own process group, and ended with the runner.

The runner ends the launch from a ``finally``: SIGINT to the whole group (roslaunch's own clean
shutdown, as Ctrl-C in a terminal), SIGKILL after ``grace`` seconds. Python runs no ``finally`` for
a SIGTERM (what ``kill``, ``timeout`` and process supervisors send), so a runner ended that way
used to leave its simulator running in its own session: :func:`sigterm_as_exit` turns SIGTERM into
``SystemExit`` for the runner's main thread, and the ``finally`` runs.
"""
import os
import signal
import socket
import subprocess


def free_port(host="127.0.0.1"):
    """A TCP port nobody listens on now (for a ROS master of one's own)."""
    with socket.socket() as s:
        s.bind((host, 0))
        return s.getsockname()[1]


def _exit_on_sigterm(signum, _frame):
    raise SystemExit(128 + signum)


def sigterm_as_exit():
    """From now on SIGTERM raises SystemExit(143) in the main thread, so that ``finally`` blocks
    (and context managers) end what the runner started. Call it from the main thread."""
    signal.signal(signal.SIGTERM, _exit_on_sigterm)


# A runner started in the background by a shell (`make demo &`, nohup, a CI script) inherits an
# ignored SIGINT, and an ignored signal stays ignored across exec: Python would install no
# KeyboardInterrupt handler in roslaunch, which would then never see the Ctrl-C that stop() sends
# (only the SIGKILL after the grace). coreutils' env puts it back to its default (no preexec_fn:
# a runner may have threads; scripts/docs_test.py starts its blocks the same way).
CTRL_C_ENDS = ("env", "--default-signal=INT")


def start(args, log, port=None, program=("roslaunch",)):
    """``roslaunch -p PORT ARGS...`` in a process group of its own (SIGINT at its default, whatever
    the runner inherited), its output to ``log`` (an open file or subprocess.PIPE); sets this
    process's ROS_MASTER_URI to that master. Returns the Popen."""
    port = port or free_port()
    os.environ["ROS_MASTER_URI"] = "http://127.0.0.1:%d" % port
    argv = list(CTRL_C_ENDS) + list(program) + ["-p", str(port)] + [str(a) for a in args]
    return subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def _signal(proc, sig):
    """``sig`` to the process group ``proc`` leads (its own session: start()), else to ``proc``."""
    try:
        if os.getpgid(proc.pid) == proc.pid:
            os.killpg(proc.pid, sig)
        else:
            proc.send_signal(sig)
    except ProcessLookupError:
        pass


def stop(proc, grace=30.0):
    """End ``proc`` and everything in the process group it leads (a launch from :func:`start`, a
    renderer and the children it restarted): SIGINT, SIGKILL when ``proc`` is not gone after
    ``grace`` seconds, and SIGKILL to what is left of its group after it ended (a child that
    ignored the SIGINT would outlive it in a session nobody watches). Returns its exit status."""
    leader = False
    if proc.poll() is None:          # not reaped: its pid is still its own
        try:
            leader = os.getpgid(proc.pid) == proc.pid
        except ProcessLookupError:
            pass
    if proc.poll() is None:
        _signal(proc, signal.SIGINT)
        try:
            proc.wait(timeout=grace)
        except subprocess.TimeoutExpired:
            _signal(proc, signal.SIGKILL)
            proc.wait()
    if leader:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    return proc.returncode
