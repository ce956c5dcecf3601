"""Process helpers the benchmark scripts share: a free port for a ROS master, the CPU time of a
process and of its threads, the processes below one, starting/stopping a command in a session of
its own (roslaunch and its nodes end together), ending a child started in the bench's own
session, and a scratch directory removed when the benchmark ends."""
import atexit
import os
import shutil
import signal
import socket
import subprocess
import tempfile


def scratch_dir(prefix):
    """A new temporary directory (under TMPDIR), removed with its contents when this process ends."""
    path = tempfile.mkdtemp(prefix=prefix)
    atexit.register(shutil.rmtree, path, True)
    return path


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def cpu_seconds(pid):
    """User + system CPU seconds of ``pid`` (all its threads) from /proc."""
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def thread_cpu_seconds(pid):
    """{thread id: user + system CPU seconds} of every thread of ``pid`` (empty once it ended)."""
    out = {}
    try:
        tids = os.listdir("/proc/%d/task" % pid)
    except OSError:
        return out
    for tid in tids:
        try:
            with open("/proc/%d/task/%s/stat" % (pid, tid)) as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        out[int(tid)] = (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    return out


def descendants(pid):
    """Every process below ``pid``, from a snapshot of /proc (children in sessions of their own
    included: roslaunch's nodes, a renderer's Xvfb)."""
    children = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % d) as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue
        children.setdefault(ppid, []).append(int(d))
    out, todo = [], [pid]
    while todo:
        for c in children.get(todo.pop(), []):
            out.append(c)
            todo.append(c)
    return out


def start(cmd, env, log=None):
    """``cmd`` in a new session; its output to ``log`` (a path) or nowhere."""
    out = open(log, "w") if log else subprocess.DEVNULL
    return subprocess.Popen(cmd, env=env, stdout=out, stderr=subprocess.STDOUT if log else subprocess.DEVNULL,
                            start_new_session=True)


def stop(proc, timeout=20.0):
    """SIGINT to the process group (as Ctrl-C), SIGKILL after ``timeout`` s."""
    if proc is None or proc.poll() is not None:
        return
    os.killpg(proc.pid, 2)
    try:
        proc.wait(timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, 9)
        proc.wait()


def terminate(proc, timeout=10.0, sig=signal.SIGTERM):
    """``sig`` to ``proc`` alone (a node started in the bench's own session, where a signal to the
    group would reach the bench), SIGKILL when it has not ended within ``timeout`` s."""
    if proc is None or proc.poll() is not None:
        return
    proc.send_signal(sig)
    try:
        proc.wait(timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
