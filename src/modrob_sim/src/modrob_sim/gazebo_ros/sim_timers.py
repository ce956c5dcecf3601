"""Callbacks every so many seconds of simulated time, for ROS helpers inside the node (actionlib's
goal status array at ``status_frequency``).

rospy's Timer sleeps on rospy's time condition, which the node notifies once per batch of steps:
in a Bulbs and Slides run that woke actionlib's 5 Hz status thread about 1500 times a wall second,
each time taking the interpreter's lock from the simulation loop, to find that 0.2 s had not
passed yet. A :class:`SimTimers` is checked by the loop after each batch (one comparison) and
hands a due callback to the node's publishing thread (:class:`~.publishing.PublishQueue`): nobody
wakes in between, and the callback does not run in the loop. When time moves backwards
(reset_simulation, reset_world) every timer starts a new period from the new time; rospy's Timer
ended its thread there, and the status array stopped for good.
"""
import threading

import rospy

#: simulated times are sums of float steps: a timer due within this of ``t`` is due at ``t``
EPS = 1e-9


class SimTimer(object):
    """One periodic callback; ``shutdown()`` stops it (a call already handed over still runs)."""

    def __init__(self, timers, period, callback, name):
        self.period = float(period)
        self.callback = callback
        self.name = name
        self.pub = None             # PublishQueue's owner interface: the build publishes nothing
        self.due = 0.0
        self.last_expected = None
        self.last_real = None
        self._timers = timers

    def shutdown(self):
        self._timers.remove(self)

    def build(self, expected, real):
        """Run in the publishing thread: the callback with a rospy TimerEvent, as rospy's Timer."""
        event = rospy.timer.TimerEvent(self.last_expected, self.last_real, expected, real, None)
        self.last_expected, self.last_real = expected, real
        self.callback(event)


class SimTimers(object):
    """The node's timers in simulated time. ``tick(t)`` is the loop's, after each batch; ``add`` and
    ``remove`` may come from any thread."""

    def __init__(self, queue):
        self._queue = queue
        self._lock = threading.Lock()
        self._timers = ()
        self._next = float("inf")     # the earliest due time: tick's one comparison
        self._t = 0.0

    def add(self, period, callback, name="timer"):
        if not period > 0.0:
            raise ValueError("%s: period must be > 0 s, got %r" % (name, period))
        timer = SimTimer(self, period, callback, name)
        with self._lock:
            timer.due = self._t + timer.period
            self._timers += (timer,)
            self._next = min(self._next, timer.due)
        return timer

    def remove(self, timer):
        with self._lock:
            self._timers = tuple(x for x in self._timers if x is not timer)
            self._next = self._earliest()
        self._queue.forget(timer)

    def tick(self, t):
        """Simulated time is now ``t`` [s]: hand every due callback to the publishing thread."""
        if self._next > t + EPS and t >= self._t:
            self._t = t
            return
        with self._lock:
            back = t < self._t
            self._t = t
            for timer in self._timers:
                if back:                    # a reset: a new period from the new time
                    timer.due = t + timer.period
                    timer.last_expected = timer.last_real = None
                elif timer.due <= t + EPS:
                    expected = rospy.Time.from_sec(timer.due)
                    real = rospy.Time.from_sec(t)
                    self._queue.put(timer, lambda x=timer, e=expected, r=real: x.build(e, r))
                    while timer.due <= t + EPS:   # a late loop skips periods, as rospy's Rate does
                        timer.due += timer.period
            self._next = self._earliest()

    def _earliest(self):
        return min([x.due for x in self._timers] or [float("inf")])
