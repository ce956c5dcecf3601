"""The one simulation loop thread of the /gazebo node (pure: no rospy; clock and sleep injected).

Every access to the physics World happens in this thread: the loop steps the world (paced to a
real-time factor, or as fast as possible), and runs, between steps, the jobs that ROS callbacks
submit with :meth:`SimulationLoop.call` (spawn, delete, set state, step N while paused ...).
The World's step hooks (controllers, publishers) therefore also run in this thread.
"""
import collections
import math
import threading
import time

from modrob_sim.errors import InputError, LoopStoppedError, SimulationError


class _Job(object):
    __slots__ = ("fn", "done", "result", "error")

    def __init__(self, fn):
        self.fn = fn
        self.done = threading.Event()
        self.result = None
        self.error = None


class SimulationLoop(object):
    """Steps ``world`` in its own thread.

    real_time_factor  1.0 keeps wall-clock pace, 2.0 twice as fast, 0 (or less) as fast as possible
    paused            start paused
    batch             most steps run between two looks at the job queue (latency vs. overhead)
    on_rtf(rtf, sim_time)   called about every ``rtf_period`` wall seconds with the measured factor
    on_error(exc)     called when world.step raises (the loop pauses physics and keeps serving)
    step(n)           steps the world n steps (default world.step; the node's batches of native steps)
    """

    def __init__(self, world, real_time_factor=1.0, paused=False, batch=10, rtf_period=1.0,
                 on_rtf=None, on_error=None, clock=time.monotonic, sleep_max=0.02, step=None):
        self.world = world
        self._step = step or world.step
        self._rtf = float(real_time_factor)
        self._paused = bool(paused)
        self._batch = max(1, int(batch))
        self._rtf_period = float(rtf_period)
        self._on_rtf = on_rtf
        self._on_error = on_error
        self._clock = clock
        self._sleep_max = sleep_max
        self._jobs = collections.deque()
        self._cond = threading.Condition()
        self._stop = False
        self._interrupted = False   # shutting down: long jobs end now, the loop still serves calls
        self._finished = False      # set when run() has returned: calls are refused from then on
        self._thread = None
        self._ref = None            # (wall, sim) at which pacing was anchored
        self._meas = None           # (wall, sim) of the last RTF measurement
        self.measured_rtf = 0.0

    # ---- state, safe from any thread ------------------------------------------------------
    @property
    def paused(self):
        return self._paused

    @property
    def stopping(self):
        """True once stop() or interrupt() was called: long jobs check it between chunks of work."""
        return self._stop or self._interrupted

    def interrupt(self):
        """The node is shutting down: a long job in progress (a step request of millions of steps)
        ends at its next chunk, so that the shutdown's own calls get the loop at once; calls are
        still served until stop()."""
        self._interrupted = True

    @property
    def real_time_factor(self):
        return self._rtf

    def set_paused(self, paused):
        with self._cond:
            self._paused = bool(paused)
            self._ref = None
            self._cond.notify_all()

    def set_real_time_factor(self, rtf):
        if not math.isfinite(rtf):
            raise InputError("real_time_factor must be finite, got %r" % rtf)
        with self._cond:
            self._rtf = float(rtf)
            self._ref = None
            self._cond.notify_all()

    def reset_pacing(self):
        """Call after the simulated time jumped (reset): re-anchor pacing and RTF measurement."""
        self._ref = None
        self._meas = None

    # ---- jobs -------------------------------------------------------------------------------
    @property
    def running(self):
        """True from start() until the loop has finished (False before start and after stop)."""
        return self._thread is not None and not self._finished and not self._stop

    def in_loop_thread(self):
        return self._thread is not None and threading.current_thread() is self._thread

    def call(self, fn, timeout=30.0):
        """Run ``fn()`` in the loop thread between two physics steps and return its result (its
        exception is re-raised here). Called from the loop thread itself, runs ``fn`` at once.
        A call made before :meth:`start` (services are advertised first) waits for the loop."""
        if self.in_loop_thread():
            return fn()
        job = _Job(fn)
        with self._cond:
            # Not Thread.is_alive(): it is False until a just-started thread has begun to run,
            # which on a loaded machine refused the first spawn request of a launch file.
            if self._finished or self._stop:
                raise LoopStoppedError("the simulation loop is not running (the node is shutting down)")
            self._jobs.append(job)
            self._cond.notify_all()
        if not job.done.wait(timeout):
            raise SimulationError("the simulation loop did not answer within %.0f s" % timeout)
        if job.error is not None:
            raise job.error
        return job.result

    def _run_jobs(self):
        while self._jobs:
            job = self._jobs.popleft()
            try:
                job.result = job.fn()
            except BaseException as exc:  # noqa: B902 - handed back to the caller's thread
                job.error = exc
            job.done.set()

    # ---- thread -----------------------------------------------------------------------------
    def start(self):
        self._thread = threading.Thread(target=self.run, name="simulation_loop", daemon=True)
        self._thread.start()

    def stop(self, timeout=5.0):
        """Stop the loop thread; True when it has ended within ``timeout``."""
        with self._cond:
            self._stop = True
            self._cond.notify_all()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout)
            return not self._thread.is_alive()
        return True

    def run(self):
        while not self._stop:
            self.run_once()
        # answer jobs still queued so that no caller waits forever
        with self._cond:
            self._finished = True
            jobs, self._jobs = list(self._jobs), collections.deque()
        for job in jobs:
            job.error = LoopStoppedError("the simulation loop stopped before running the request")
            job.done.set()

    def run_once(self):
        """One pass: run queued jobs, then step what is due (or wait). Returns steps taken."""
        if self._jobs:
            self._run_jobs()
        now = self._clock()
        self._measure(now)
        if self._paused:
            with self._cond:
                if not self._jobs and not self._stop and self._paused:
                    self._cond.wait(0.05)
            return 0
        world = self.world
        n = self._batch
        if self._rtf > 0.0:
            dt = world.time_step
            sim = world.time
            if self._ref is None:
                self._ref = (now, sim)
            due = self._ref[1] + (now - self._ref[0]) * self._rtf
            ahead = sim + dt - due              # sim seconds we are ahead of the wall clock
            if ahead > 1e-12:
                wait = min(self._sleep_max, ahead / self._rtf)
                with self._cond:
                    if not self._jobs and not self._stop:
                        self._cond.wait(wait)
                return 0
            n = min(n, int((due - sim) / dt + 1e-9) or 1)
            if due - sim > 0.25 * self._rtf:    # far behind (slow machine, debugger): don't burst
                self._ref = (now, sim)
        try:
            taken = self._step(n)
        except Exception as exc:  # noqa: B902 - the node must keep serving; reported via on_error
            self._paused = True
            if self._on_error is not None:
                self._on_error(exc)
            return 0
        # a step function may end the pass early (at a step whose publishers were due)
        return n if taken is None else taken

    def _measure(self, now):
        if self._meas is None:
            self._meas = (now, self.world.time)
            return
        dw = now - self._meas[0]
        if dw < self._rtf_period:
            return
        sim = self.world.time
        self.measured_rtf = max(0.0, (sim - self._meas[1]) / dw)
        self._meas = (now, sim)
        if self._on_rtf is not None:
            self._on_rtf(self.measured_rtf, sim)
