"""The node's timers in simulated time (modrob_sim.gazebo_ros.sim_timers): due callbacks run in the
publishing thread, once per period, a new period after time moves backwards, none after shutdown."""
import queue
import threading

import pytest

from modrob_sim.gazebo_ros.publishing import PublishQueue
from modrob_sim.gazebo_ros.sim_timers import SimTimers


@pytest.fixture
def timers():
    q = PublishQueue()
    yield SimTimers(q)
    q.stop()


class Calls(object):
    def __init__(self):
        self.q = queue.Queue()

    def __call__(self, event):
        self.q.put((event.current_expected.to_sec(), event.current_real.to_sec(),
                    threading.current_thread().name))

    def next(self):
        return self.q.get(timeout=10)

    def none(self, timers, t):
        """tick(t) hands nothing over: once a marker queued after it has run (the publishing thread
        runs in order), no call has arrived."""
        timers.tick(t)
        done = threading.Event()

        class Marker(object):
            name, pub = "marker", None
        timers._queue.put(Marker(), done.set)
        assert done.wait(10)
        assert self.q.empty()


def test_a_timer_fires_once_per_period_of_simulated_time_in_the_publishing_thread(timers):
    calls = Calls()
    timers.add(0.2, calls, "status")
    seen = []
    for i in range(1, 21):
        timers.tick(0.05 * i)
        if i % 4 == 0:
            seen.append(calls.next())
        assert calls.q.empty()
    assert [round(e, 6) for e, _r, _n in seen] == [0.2, 0.4, 0.6, 0.8, 1.0]
    assert {n for _e, _r, n in seen} == {"plugin_publishing"}


def test_a_late_tick_makes_one_call_and_the_next_period_follows_the_schedule(timers):
    calls = Calls()
    timers.add(0.2, calls)
    timers.tick(0.75)
    expected, real, _ = calls.next()
    assert (round(expected, 6), round(real, 6)) == (0.2, 0.75)
    calls.none(timers, 0.79)
    timers.tick(0.8)
    assert round(calls.next()[0], 6) == 0.8


def test_time_moving_backwards_starts_a_new_period_from_the_new_time(timers):
    calls = Calls()
    timers.add(0.2, calls)
    timers.tick(0.2)
    calls.next()
    calls.none(timers, 0.01)    # reset_simulation: no call, the next one 0.2 s later
    calls.none(timers, 0.2)
    timers.tick(0.21)
    assert round(calls.next()[0], 6) == 0.21


def test_a_timer_shut_down_is_not_called_and_the_others_go_on(timers):
    a, b = Calls(), Calls()
    ta = timers.add(0.1, a)
    timers.add(0.1, b)
    timers.tick(0.1)
    a.next()
    b.next()
    ta.shutdown()
    timers.tick(0.2)
    b.next()
    assert a.q.empty()


def test_a_period_that_is_not_positive_is_refused_by_name(timers):
    with pytest.raises(ValueError, match="status.*period"):
        timers.add(0.0, print, "status")
