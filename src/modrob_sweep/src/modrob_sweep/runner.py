"""Trials as Ray tasks: on a Ray started here (``ray.init(address="local")``, as many trials side by
side as --workers, default the machine's cores) or on a Ray cluster (``--address``).

Each trial is one task that declares the CPUs it needs (the sweep's ``cpus``), so Ray places as
many trials on a node as its CPUs allow; the scheduling, placement and node failures are Ray's.
The driver only keeps the progress line, resubmits a trial once when it could not be run (an
InfraError raised by the trial, or a worker or node lost under it: ``attempts`` 2), and records
everything else as the trial reported it (a scenario's failure, crash or hang is never re-run).

Ctrl-C (or SIGTERM) cancels every running task (``ray.cancel(force=True)``): the worker goes, so
each trial's reaper sees its parent die and stops the trial's processes; the driver then waits
until no process carrying the sweep's token is left on this machine, writes the trials that
finished, and stops the Ray it started.

Ctrl-C or SIGTERM while a local Ray starts (ray.init) stops what of it has started, at once, and ends
the process with 130 (see _signals_during_start).

A Ray started here keeps its session (logs, sockets) in a directory of its own (``ray-*`` in
RAY_TMPDIR or the system's temporary directory), which shutdown() removes: when the sweep ends, on
an error and after Ctrl-C or SIGTERM. A process that could not (killed with SIGKILL) leaves it; the
next one that makes such a directory there removes it (remove_stale_ray_temp_dirs). A cluster's Ray
keeps its sessions where its nodes were started.
"""
import contextlib
import glob
import os
import shutil
import signal
import socket
import sys
import tempfile
import threading
import time
import uuid

from modrob_sim.procs import start_time
from modrob_sweep import InfraError, SweepError
from modrob_sweep.trial import run_trial

SWEEP_VAR = "MODROB_SWEEP_ID"
# Ray kills a dead worker's child processes with SIGKILL by default: that would be each trial's
# reaper, before it could stop its trial (roscore, simulator ... orphaned). Off, the reaper sees its
# parent die (PR_SET_PDEATHSIG) and stops the trial itself. Nodes of a cluster want the same
# (docs/sweeps.md).
RAY_CHILD_KILL = "RAY_kill_child_processes_on_worker_exit"
CANCEL_GRACE_S = 30.0
# A Unix socket's path has at most 107 bytes; Ray makes its sockets at <temp dir>/<session>/sockets/
# (the session named by date, time and a pid of up to 7 digits; plasma_store the longest name).
SOCKET_PATH_MAX = 107
RAY_SOCKET_TAIL = len("/session_2026-01-01_00-00-00_000000_1234567/sockets/plasma_store")
RAY_TEMP_PREFIX = "ray-"
# the longest directory in which Ray's own (RAY_TEMP_PREFIX + 8 characters) leaves room for its sockets
RAY_TEMP_BASE_MAX = SOCKET_PATH_MAX - RAY_SOCKET_TAIL - len("/%sxxxxxxxx" % RAY_TEMP_PREFIX)
SHORT_TEMP = "/tmp"          # where Ray's directory goes when the temporary directory's path is too long
# in each such directory: "<pid> <start time>" of the process that made it (remove_stale_ray_temp_dirs)
OWNER_FILE = "modrob_sweep.owner"
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
CRASH_MARK = b" received at time="       # Ray's crash handler: "*** SIGSEGV received at time=... ***"
CRASH_LOGS = "ray_crash_logs"
EXIT_INTERRUPTED = 130
# (path, RAY_TMPDIR before) of the Ray this process started, until shutdown()
_ray_temp_dirs = []


class Progress(object):
    """One line per finished trial (and a refreshed line on a terminal) with counts and the ETA."""

    def __init__(self, total, stream=None, workers=1):
        self.total, self.done, self.t0 = total, 0, time.monotonic()
        self.counts = {}
        self.stream = stream or sys.stdout
        self.workers = workers

    def eta(self):
        if self.done == 0:
            return None
        elapsed = time.monotonic() - self.t0
        return elapsed / self.done * (self.total - self.done)

    def line(self, running=0):
        """The progress line; ``running`` is the number of trials not finished (at most ``workers``
        of them run at a time)."""
        el = time.monotonic() - self.t0
        eta = self.eta()
        bar_n = 24
        filled = int(round(bar_n * self.done / float(self.total))) if self.total else bar_n
        counts = ", ".join("%s %d" % (k, v) for k, v in sorted(self.counts.items()))
        return "[sweep] [%s%s] %d/%d done%s, %d running, %s elapsed, ETA %s" % (
            "#" * filled, "." * (bar_n - filled), self.done, self.total, (" (%s)" % counts) if counts else "",
            min(running, self.workers), _hms(el), _hms(eta) if eta is not None else "?")

    def finished(self, row, running):
        self.done += 1
        self.counts[row["outcome"]] = self.counts.get(row["outcome"], 0) + 1
        print("[sweep] trial %d on %s: %s in %.1f s%s" % (
            row["trial"], row["host"], row["outcome"], row["wall_s"],
            "" if row["outcome"] == "success" else " (%s)" % row.get("detail", "")), file=self.stream)
        print(self.line(running), file=self.stream, flush=True)


def _hms(s):
    s = int(round(s))
    return "%d:%02d:%02d" % (s // 3600, s % 3600 // 60, s % 60) if s >= 3600 else "%d:%02d" % (s // 60,
                                                                                               s % 60)


def _remote_trial():
    import ray

    @ray.remote(max_retries=0)
    def trial_task(task, trial, out_root, token, attempt):
        return run_trial(task, trial, out_root, token, attempt)
    return trial_task


def connect(address=None, workers=None, cpus_per_trial=1.0, token=None, quiet=True):
    """ray.init on this machine (a private instance with ``workers`` x ``cpus_per_trial`` CPUs) or
    on the cluster at ``address``. Returns the number of CPUs the trials can use. SIGINT and SIGTERM
    keep the handlers they had (ray.init puts its own in place for SIGTERM); one that comes while Ray
    starts ends the process (_signals_during_start)."""
    try:
        import ray
    except ImportError as exc:
        raise SweepError("Ray is not installed in this environment (%s): run `make setup` (requirements.txt "
                         "pins ray[tune]) and `source scripts/env.sh`" % exc)
    if token:
        os.environ[SWEEP_VAR] = token       # the local Ray's processes inherit it: the Ctrl-C test finds them
    os.environ.setdefault(RAY_CHILD_KILL, "0")
    kw = {"include_dashboard": False, "log_to_driver": not quiet, "logging_level": "warning"}
    if address:
        try:
            with _signals_during_start(token):
                ray.init(address=address, **kw)
        except (ConnectionError, RuntimeError, ValueError) as exc:
            raise SweepError("cannot join the Ray cluster at %s: %s. Start it first (`ray start --head` on "
                             "the head, `ray start --address=<head>:6379` on each node, docs/sweeps.md)"
                             % (address, exc))
    else:
        n = workers or os.cpu_count() or 1
        kw["_temp_dir"] = new_ray_temp_dir()
        for attempt in (1, 2):
            try:
                with _signals_during_start(token):
                    ray.init(address="local", num_cpus=max(1, int(round(n * cpus_per_trial))), **kw)
                break
            except Exception as exc:     # noqa: B902 Ray raises a bare Exception when its node does not start
                ray.shutdown()           # what did start of it
                reason = str(exc).strip().splitlines()[-1] if str(exc).strip() else type(exc).__name__
                if attempt == 1:         # Ray gives its node 30 s to register: a loaded machine needs more
                    print("sweep: Ray did not start on this machine (%s); trying once more" % reason,
                          file=sys.stderr, flush=True)
                    continue
                _remove_ray_temp_dirs()
                raise SweepError("Ray did not start on this machine, twice: %s. On an overloaded machine its "
                                 "start-up times out: run the sweep again (or with fewer --workers)" % reason)
    return ray.cluster_resources().get("CPU", 0)


@contextlib.contextmanager
def _signals_during_start(token):
    """Around ray.init: SIGINT or SIGTERM during it stops what of Ray has started (its processes carry
    ``token`` in their environment), removes its directory and ends this process with 130, at once.

    The signals' handlers cannot do that: Python runs a handler only between two bytecodes of the main
    thread, and ray.init spends seconds inside Ray's C++ start-up (its core worker waits for the
    raylet), where none runs; and Ray's crash handler, installed during that start-up, ends the process
    on a SIGTERM, leaving Ray's processes and directory behind. So the two signals are blocked during
    the start (also in the threads Ray starts, which inherit that) and a thread waits for them. After
    the start the handlers in place before are put back and the signals unblocked: one that came in
    between goes to them."""
    if threading.current_thread() is not threading.main_thread():   # signals go to the main thread's
        yield                                                         # handlers, set by its caller
        return
    handlers = {s: signal.getsignal(s) for s in STOP_SIGNALS}
    signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
    started = threading.Event()

    def wait_for_signal():
        while not started.is_set():
            info = signal.sigtimedwait(STOP_SIGNALS, 0.05)
            if info is not None:
                _abandon_start(token, info.si_signo)
    waiter = threading.Thread(target=wait_for_signal, name="ray_start_signals", daemon=True)
    waiter.start()
    try:
        yield
    finally:
        started.set()
        waiter.join()
        for sig, handler in handlers.items():
            if handler is not None:
                signal.signal(sig, handler)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)


def _abandon_start(token, signum):
    """A signal while Ray starts: stop Ray's processes, remove its directory, end the process."""
    print("\n[sweep] %s while Ray was starting: stopping it" % signal.Signals(signum).name, file=sys.stderr,
          flush=True)
    if token:
        _wait_local_trials(token, kill=True, timeout=0.0)
    _remove_ray_temp_dirs()
    sys.stdout.flush()
    os._exit(EXIT_INTERRUPTED)


def interrupt_on_sigterm():
    """SIGTERM raises KeyboardInterrupt from now on, as Ctrl-C does (a driver's clean-up runs on
    either); returns the handler it had."""
    return signal.signal(signal.SIGTERM, _raise_interrupt)


def new_ray_temp_dir():
    """A fresh directory for the session of a Ray started here (ray.init's _temp_dir, `ray start
    --temp-dir`), in RAY_TMPDIR or the system's temporary directory, /tmp when that path is too long for
    Ray's socket paths. RAY_TMPDIR is set to it until shutdown() removes it. Those that processes which
    ended without removing theirs left in the same place are removed first."""
    base = os.path.abspath(os.environ.get("RAY_TMPDIR") or tempfile.gettempdir())
    if len(base) > RAY_TEMP_BASE_MAX:
        print("sweep: the temporary directory %s is too long for Ray's socket paths in it (%d bytes at "
              "most): Ray's session goes to %s" % (base, RAY_TEMP_BASE_MAX, SHORT_TEMP), file=sys.stderr,
              flush=True)
        base = SHORT_TEMP
    remove_stale_ray_temp_dirs(base)
    path = tempfile.mkdtemp(prefix=RAY_TEMP_PREFIX, dir=base)
    with open(os.path.join(path, OWNER_FILE), "w") as fh:
        fh.write("%d %d\n" % (os.getpid(), start_time(os.getpid())))
    _ray_temp_dirs.append((path, os.environ.get("RAY_TMPDIR")))
    # Ray's other temporary files (Ray Tune's lock files) go there too, in this process and in the
    # Ray processes, which inherit the environment
    os.environ["RAY_TMPDIR"] = path
    return path


def remove_stale_ray_temp_dirs(base):
    """Remove the ``ray-*`` directories in ``base`` that new_ray_temp_dir made for a process that has
    ended (killed with SIGKILL: its clean-up never ran), after stopping the Ray processes still using
    one (Ray's agents outlive their raylet for a minute). Those of running processes, and directories
    without an owner file (not made here), are left alone. Returns the paths removed."""
    removed = []
    try:
        names = sorted(os.listdir(base))
    except OSError:
        return removed
    for name in names:
        path = os.path.join(base, name)
        if not name.startswith(RAY_TEMP_PREFIX):
            continue
        try:
            with open(os.path.join(path, OWNER_FILE)) as fh:
                pid, started = (int(v) for v in fh.read().split())
        except (OSError, ValueError):
            continue
        if start_time(pid) == started:
            continue
        for left in _with_var("RAY_TMPDIR", path):
            if left == os.getpid():
                continue
            try:
                os.kill(left, signal.SIGKILL)
            except ProcessLookupError:
                pass
        shutil.rmtree(path, ignore_errors=True)
        print("sweep: removed %s, the Ray directory of process %d, which ended without removing it (killed?)"
              % (path, pid), file=sys.stderr, flush=True)
        removed.append(path)
    return removed


def keep_crash_logs(out_root, stream=None):
    """Copy the logs of the local Ray's processes that crashed (a worker under a trial, the raylet: Ray's
    crash handler writes "*** SIGSEGV received at time=..." and the stack into the process's .err log)
    to ``<out_root>/ray_crash_logs/`` and name them on ``stream``: shutdown() removes the session's
    directory, and a lost trial's row only says that its worker died. Returns the copies' paths."""
    kept = []
    for temp_dir, _before in _ray_temp_dirs:
        for logs in sorted(glob.glob(os.path.join(temp_dir, "session_*", "logs"))):
            if os.path.islink(os.path.dirname(logs)):          # session_latest, the same session again
                continue
            for path in sorted(glob.glob(os.path.join(logs, "*.err"))):
                try:
                    with open(path, "rb") as fh:
                        crashed = CRASH_MARK in fh.read()
                except OSError:
                    continue
                if crashed:
                    os.makedirs(os.path.join(out_root, CRASH_LOGS), exist_ok=True)
                    kept.append(shutil.copy(path, os.path.join(out_root, CRASH_LOGS)))
                    print("[sweep] a Ray process crashed: its log with the stack trace is in %s" % kept[-1],
                          file=stream or sys.stderr, flush=True)
    return kept


def _remove_ray_temp_dirs():
    while _ray_temp_dirs:
        path, before = _ray_temp_dirs.pop()
        shutil.rmtree(path, ignore_errors=True)
        if before is None:
            os.environ.pop("RAY_TMPDIR", None)
        else:
            os.environ["RAY_TMPDIR"] = before


def shutdown(token=None):
    """Stop this process's Ray (nothing when none runs); with ``token`` (connect's), wait until the local
    Ray's processes are gone (killed after a while), so that nothing writes its temporary directory any
    more; then remove that directory."""
    ray = sys.modules.get("ray")         # not imported: no Ray ran in this process
    try:
        # a Ray whose start was cut short (a signal in ray.init) is not shut down by ray.shutdown: what
        # it started is stopped at once rather than waited for
        started = ray is not None and ray.is_initialized()
        if ray is not None:
            ray.shutdown()
        if token:
            _wait_local_trials(token, kill=True, timeout=20.0 if started else 0.0)
    finally:
        _remove_ray_temp_dirs()


def run(sweep, out_root, address=None, workers=None, progress_stream=None, on_row=None):
    """Run every trial of ``sweep``; returns (rows, interrupted). Rows are what run_trial returned,
    or rows made here for trials that could not be run twice or were cancelled."""
    token = "%s-%s" % (sweep.name, uuid.uuid4().hex[:10])
    stream = progress_stream or sys.stdout
    pending = {}
    rows = []
    interrupted = False
    old_term = interrupt_on_sigterm()
    # Ctrl-C stops the sweep even when it was started with SIGINT ignored (a background job of a
    # script inherits that): the trials must never be left to run on
    old_int = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        total_cpus = connect(address, workers, sweep.cpus, token)
        import ray
        if total_cpus < sweep.cpus:
            raise SweepError("one trial of %s needs %g CPUs but the Ray cluster has %g: lower `cpus` in the "
                             "sweep file or add nodes" % (sweep.name, sweep.cpus, total_cpus))
        side_by_side = int(total_cpus // sweep.cpus)
        task = sweep.as_task()
        trial_task = _remote_trial().options(num_cpus=sweep.cpus)
        os.makedirs(out_root, exist_ok=True)
        progress = Progress(len(sweep.trials), stream, side_by_side)
        print("[sweep] %s: %d trials, %g CPU each, up to %d side by side on %s; results in %s"
              % (sweep.name, len(sweep.trials), sweep.cpus, side_by_side,
                 "the Ray cluster at %s" % address if address else "this machine (%s)" % socket.gethostname(),
                 out_root), file=stream, flush=True)
        for t in sweep.trials:
            ref = trial_task.remote(task, t.as_dict(), out_root, token, 1)
            pending[ref] = (t, 1)
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=5.0)
            for ref in ready:
                t, attempt = pending.pop(ref)
                row, retry = _collect(ref, t, attempt)
                if retry:
                    print("[sweep] trial %d could not be run (%s): once more" % (t.index, retry),
                          file=progress.stream, flush=True)
                    again = trial_task.remote(task, t.as_dict(), out_root, token, attempt + 1)
                    pending[again] = (t, attempt + 1)
                    continue
                rows.append(row)
                if on_row:
                    on_row(row)
                progress.finished(row, len(pending))
    except KeyboardInterrupt:
        interrupted = True
        signal.signal(signal.SIGINT, signal.SIG_IGN)    # a second Ctrl-C must not cut the clean-up short
        print("\n[sweep] interrupted: stopping %d running trial(s)" % len(pending), file=stream, flush=True)
        if pending:
            _cancel(list(pending), stream)
    finally:
        signal.signal(signal.SIGTERM, old_term)
        signal.signal(signal.SIGINT, signal.SIG_IGN)    # a second Ctrl-C must not cut the clean-up short
        try:
            _wait_local_trials(token)
            keep_crash_logs(out_root, stream)
            shutdown(token)
        finally:
            signal.signal(signal.SIGINT, old_int)
    return rows, interrupted


def _cancel(refs, stream):
    """Cancel the trials: first as a KeyboardInterrupt in each task (run_trial then has its reaper
    stop the trial, SIGINT before SIGKILL), after CANCEL_GRACE_S by killing the workers left."""
    import ray
    for force in (False, True):
        for ref in refs:
            try:
                ray.cancel(ref, force=force)
            except (ValueError, TypeError, ray.exceptions.RayError) as exc:   # the reaper stops it anyway
                print("[sweep] could not cancel a trial: %s" % exc, file=stream)
        if force:
            return
        done, refs = ray.wait(refs, num_returns=len(refs), timeout=CANCEL_GRACE_S)
        if not refs:
            return


def _raise_interrupt(signum, frame):
    raise KeyboardInterrupt()


def _collect(ref, t, attempt):
    """(row, None) for a finished trial, (None, reason) when it should be run once more."""
    import ray
    try:
        return ray.get(ref), None
    except ray.exceptions.RayTaskError as exc:
        cause = exc.as_instanceof_cause()
        if isinstance(cause, InfraError):
            reason, outcome = str(cause).splitlines()[-1], "infra_error"
        else:
            return _row(t, "error", attempt, "the trial's task failed: %s" % str(exc).splitlines()[-1]), None
    except (ray.exceptions.WorkerCrashedError, ray.exceptions.NodeDiedError, ray.exceptions.ObjectLostError,
            ray.exceptions.OwnerDiedError, ray.exceptions.RaySystemError) as exc:
        reason, outcome = "%s: %s" % (type(exc).__name__, str(exc).splitlines()[0]), "lost"
    if attempt < 2:
        return None, reason
    return _row(t, outcome, attempt, reason), None


def _row(t, outcome, attempt, detail):
    return {"trial": t.index, "host": "", "outcome": outcome, "wall_s": float("nan"), "sim_s": float("nan"),
            **t.params, "seed": t.seed, "attempts": attempt, "detail": detail, "out": ""}


def _wait_local_trials(token, kill=False, timeout=20.0):
    """Wait until no process of this sweep (its trials; with ``kill`` the local Ray's too) is left on
    this machine; what is still there after ``timeout`` is stopped here and named."""
    me = os.getpid()
    deadline = time.monotonic() + timeout
    while True:
        left = [p for p in _with_var(SWEEP_VAR, token, trials_only=not kill) if p != me]
        if not left or time.monotonic() > deadline:
            break
        time.sleep(0.1)
    if left:
        names = []
        for pid in left[:4]:
            try:
                with open("/proc/%d/cmdline" % pid, "rb") as fh:
                    names.append(b" ".join(fh.read().split(b"\0")).decode(errors="replace")[:60].strip())
            except OSError:
                pass
        print("[sweep] stopping %d process(es) the sweep left on this machine after %g s (%s)"
              % (len(left), timeout, ", ".join(names)), file=sys.stderr)
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


def _with_var(var, value, trials_only=False):
    """pids of this sweep's trials (their MODROB_SWEEP_TRIAL starts with the token) and, unless
    trials_only, of every process whose environment has var=value (the local Ray's)."""
    want = ("%s=%s" % (var, value)).encode()
    trial = ("MODROB_SWEEP_TRIAL=%s-" % value).encode()
    out = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open("/proc/%s/environ" % entry, "rb") as fh:
                env = fh.read().split(b"\0")
        except OSError:
            continue
        in_trial = any(e.startswith(trial) for e in env)
        if in_trial or (not trials_only and want in env):
            out.append(int(entry))
    return out
