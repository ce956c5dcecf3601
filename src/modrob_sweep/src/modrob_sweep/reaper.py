"""The supervisor of one trial: runs the scenario's command and, whatever happens, leaves none of its
processes behind (roscore, the simulator, the renderer, an Xvfb).

    python3 -m modrob_sweep.reaper --token T --parent PID --status FILE [--xvfb] -- COMMAND...

Scenario programs start their own process groups and sessions (roslaunch, the demos' masters), so a
process-group kill does not reach them. The reaper instead makes itself the *child subreaper* of
everything below it (Linux prctl PR_SET_CHILD_SUBREAPER: an orphaned descendant is re-parented to
it, not to init), marks the trial's environment with MODROB_SWEEP_TRIAL=<token>, and when the
command ends, when it is told to stop (SIGTERM/SIGINT/SIGHUP) or when its parent - the Ray worker -
dies (PR_SET_PDEATHSIG), it stops every descendant and every process carrying the token: SIGINT
first (roslaunch shuts its nodes down cleanly), SIGKILL after a grace period.

The status FILE (JSON) says how the command ended: exit, signal, stopped (told to stop), infra (the
trial could not be set up, e.g. no Xvfb), leftovers (processes the command left running).
Exit code: the command's, 128 + signal if it was killed, 75 when the set-up failed.
"""
import argparse
import ctypes
import json
import os
import select
import signal
import subprocess
import sys
import time

PR_SET_PDEATHSIG = 1
PR_SET_CHILD_SUBREAPER = 36
TOKEN_VAR = "MODROB_SWEEP_TRIAL"
EX_TEMPFAIL = 75
GRACE_S = 5.0


class Stop(Exception):
    """Raised from a signal handler: the reaper was told to stop the trial."""


def _prctl(option, value):
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.prctl(option, value, 0, 0, 0) != 0:
        raise OSError(ctypes.get_errno(), "prctl(%d) failed" % option)


def _stat(pid):
    """(ppid, state) of a process, or None if it is gone."""
    try:
        with open("/proc/%d/stat" % pid) as fh:
            text = fh.read()
    except OSError:
        return None
    rest = text[text.rindex(")") + 2:].split()
    return int(rest[1]), rest[0]


def _has_token(pid, token):
    try:
        with open("/proc/%d/environ" % pid, "rb") as fh:
            return ("%s=%s" % (TOKEN_VAR, token)).encode() in fh.read().split(b"\0")
    except OSError:
        return False


def _name(pid):
    """The command line of a process (None when it is gone)."""
    try:
        with open("/proc/%d/cmdline" % pid, "rb") as fh:
            return " ".join(a.decode(errors="replace") for a in fh.read().split(b"\0") if a)[:120] or None
    except OSError:
        return None


def _under(pid, ancestor):
    """Whether ``pid`` is ``ancestor`` or below it (False for a process that is gone)."""
    while ancestor and pid > 1:
        if pid == ancestor:
            return True
        st = _stat(pid)
        if st is None:
            return True          # gone: nothing to report
        pid = st[0]
    return False


def members(root, token):
    """Live processes of the trial: descendants of ``root`` and every process carrying ``token``."""
    children, tokened = {}, set()
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        pid = int(entry)
        st = _stat(pid)
        if st is None or st[1] == "Z":
            continue
        children.setdefault(st[0], []).append(pid)
        if token and pid != root and _has_token(pid, token):
            tokened.add(pid)
    found, todo = set(), [root]
    while todo:
        for c in children.get(todo.pop(), []):
            if c not in found:
                found.add(c)
                todo.append(c)
    return (found | tokened) - {root, os.getpid()}


def _reap():
    while True:
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return


def stop_all(token, grace=GRACE_S):
    """SIGINT to every process of the trial, SIGKILL to those left after ``grace`` seconds; returns
    the command lines of the processes that were found running."""
    me = os.getpid()
    first = members(me, token)
    names = [n for n in (_name(p) for p in sorted(first)) if n is not None]
    for sig, wait in ((signal.SIGINT, grace), (signal.SIGKILL, 5.0)):
        live = members(me, token)
        for pid in live:
            try:
                os.kill(pid, sig)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + wait
        while live and time.monotonic() < deadline:
            _reap()
            live = members(me, token)
            if live:
                time.sleep(0.05)
        if not live:
            break
    _reap()
    return names


def _start_xvfb(env):
    """An Xvfb on a free display (it picks the number and writes it to a pipe): (display, pid)."""
    r, w = os.pipe()
    try:
        proc = subprocess.Popen(["Xvfb", "-displayfd", str(w), "-screen", "0", "1280x1024x24", "-nolisten",
                                 "tcp"],
                                pass_fds=(w,), env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except OSError as exc:
        raise RuntimeError("Xvfb could not be started (%s): install the xvfb package on this node" % exc)
    finally:
        os.close(w)
    # read up to the newline before closing: Xvfb may write the number and the newline apart, and a
    # write to a closed pipe is fatal to it
    text, deadline = b"", time.monotonic() + 30.0
    while not text.endswith(b"\n") and time.monotonic() < deadline:
        ready, _, _ = select.select([r], [], [], max(0.0, deadline - time.monotonic()))
        chunk = os.read(r, 64) if ready else b""
        if not chunk:
            break
        text += chunk
    os.close(r)
    number = text.decode().strip()
    if not number.isdigit():
        proc.kill()
        raise RuntimeError("Xvfb did not report a display within 30 s (exit %s)" % proc.poll())
    return ":" + number, proc.pid


def main(argv=None):
    p = argparse.ArgumentParser(prog="modrob_sweep.reaper", description=__doc__.splitlines()[0])
    p.add_argument("--token", required=True)
    p.add_argument("--parent", type=int, required=True, help="pid of the process that must stay alive")
    p.add_argument("--status", required=True)
    p.add_argument("--xvfb", action="store_true")
    p.add_argument("command", nargs=argparse.REMAINDER)
    args = p.parse_args(argv)
    cmd = args.command[1:] if args.command[:1] == ["--"] else args.command
    status = {"exit": None, "signal": None, "stopped": False, "infra": None, "leftovers": []}

    # A Ray worker runs tasks with signals blocked; a blocked mask is inherited through fork and exec,
    # and roscore, rosout and the nodes would then ignore roslaunch's SIGINT (15 s each to SIGTERM).
    signal.pthread_sigmask(signal.SIG_SETMASK, set())

    def on_signal(signum, _frame):
        raise Stop(signum)
    for s in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(s, on_signal)
    code = 0
    try:
        _prctl(PR_SET_CHILD_SUBREAPER, 1)
        _prctl(PR_SET_PDEATHSIG, signal.SIGTERM)
        if os.getppid() != args.parent:      # the parent died before PDEATHSIG was armed
            raise Stop(signal.SIGTERM)
        env = dict(os.environ, **{TOKEN_VAR: args.token})
        xvfb = None
        try:
            if args.xvfb:
                env["DISPLAY"], xvfb = _start_xvfb(env)
            child = subprocess.Popen(cmd, env=env)
        except (RuntimeError, OSError) as exc:
            status["infra"] = "%s: %s" % (cmd[0] if cmd else "command", exc)
            code = EX_TEMPFAIL
        else:
            while True:
                pid, st = os.waitpid(-1, 0)
                if pid == child.pid:
                    break
            if os.WIFSIGNALED(st):
                status["signal"] = os.WTERMSIG(st)
                code = 128 + status["signal"]
            else:
                status["exit"] = code = os.WEXITSTATUS(st)
            # the trial's own display (and the xkbcomp it runs) is no leftover of the scenario
            left = [pid for pid in sorted(members(os.getpid(), args.token)) if not _under(pid, xvfb)]
            status["leftovers"] = [n for n in (_name(pid) for pid in left) if n is not None]
    except Stop:
        status["stopped"] = True
        code = 128 + signal.SIGTERM
    finally:
        for s in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
            signal.signal(s, signal.SIG_IGN)     # nothing interrupts the clean-up
        stop_all(args.token)
        try:
            with open(args.status, "w") as fh:
                json.dump(status, fh)
        except OSError as exc:
            print("modrob_sweep.reaper: cannot write %s: %s" % (args.status, exc), file=sys.stderr)
    return code


if __name__ == "__main__":
    sys.exit(main())
