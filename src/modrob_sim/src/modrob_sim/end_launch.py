"""End the roslaunch a node runs in, as Ctrl-C in its terminal would.

A scenario node whose end should end its launch is usually marked ``required="true"``: roslaunch
then tears everything down, but announces it with a red "REQUIRED process [...] has died!" banner
and "Initiating shutdown!", although nothing went wrong. A node that calls :func:`end_launch`
after its work instead gets the launch stopped the ordinary way: roslaunch receives SIGINT, stops
every node with SIGINT, and ends quietly.
"""
import os
import signal
import time


def parent_is_roslaunch(ppid=None, proc="/proc"):
    """Whether the process ``ppid`` (default: this one's parent) is a ``roslaunch``."""
    ppid = os.getppid() if ppid is None else ppid
    try:
        with open(os.path.join(proc, str(ppid), "cmdline"), "rb") as f:
            argv = [a.decode(errors="replace") for a in f.read().split(b"\0") if a]
    except OSError:
        return False
    # "roslaunch ..." run directly, or "python3 /usr/bin/roslaunch ..." through its interpreter
    return any(os.path.basename(a) == "roslaunch" for a in argv[:2])


def end_launch(is_shutdown, timeout=30.0, kill=os.kill):
    """Send SIGINT to the roslaunch that started this node and wait (at most ``timeout`` wall
    seconds) until ``is_shutdown()``: roslaunch stops this node too, so that the node ends inside
    the launch's own shut-down. Returns False (and does nothing) when the parent is not a roslaunch
    (rosrun, rostest, a script): the caller then simply ends."""
    if not parent_is_roslaunch():
        return False
    kill(os.getppid(), signal.SIGINT)
    end = time.monotonic() + timeout
    while not is_shutdown() and time.monotonic() < end:
        time.sleep(0.05)
    return True


def finish_scenario(log, exit_when_done, is_shutdown):
    """What a scenario node does after its RESULT line: with ``exit_when_done`` end its launch
    (quietly, see :func:`end_launch`), else say that the world stays up."""
    if exit_when_done and end_launch(is_shutdown):
        return
    if not exit_when_done and parent_is_roslaunch():
        log("the scenario is done; the simulation stays up (exit_when_done:=false): Ctrl-C ends the launch")
