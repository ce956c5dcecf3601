"""The /gazebo node's simulation loop (pure): jobs run in the loop thread between steps, pause
stops stepping, pacing holds the real-time factor against an injected clock, step errors pause."""
import threading

import pytest

from modrob_sim.errors import SimulationError
from modrob_sim.gazebo_ros.sim_loop import SimulationLoop


class CountingWorld(object):
    """Stands in for the physics World: only time bookkeeping (the loop never looks further)."""

    def __init__(self, dt=0.001, fail_at=None):
        self.time_step = dt
        self.iterations = 0
        self.fail_at = fail_at
        self.step_threads = set()

    @property
    def time(self):
        return self.iterations * self.time_step

    def step(self, n=1):
        self.step_threads.add(threading.current_thread().name)
        if self.fail_at is not None and self.iterations + n > self.fail_at:
            raise SimulationError("boom")
        self.iterations += n


class FakeClock(object):
    def __init__(self):
        self.t = 0.0

    def __call__(self):
        return self.t


def test_paced_loop_follows_the_wall_clock():
    world, clock = CountingWorld(), FakeClock()
    loop = SimulationLoop(world, real_time_factor=1.0, clock=clock, batch=1000)
    loop.run_once()                     # anchors pacing at wall 0
    for _ in range(100):
        clock.t += 0.01
        loop.run_once()
    assert world.time == pytest.approx(clock.t, abs=0.0015)


def test_real_time_factor_two_runs_twice_as_fast():
    world, clock = CountingWorld(), FakeClock()
    loop = SimulationLoop(world, real_time_factor=2.0, clock=clock, batch=1000)
    loop.run_once()
    for _ in range(50):
        clock.t += 0.01
        loop.run_once()
    assert world.time == pytest.approx(2.0 * clock.t, abs=0.003)


def test_unlimited_steps_in_batches_without_waiting():
    world, clock = CountingWorld(), FakeClock()
    loop = SimulationLoop(world, real_time_factor=0.0, clock=clock, batch=7)
    for _ in range(10):
        loop.run_once()
    assert world.iterations == 70


def test_paused_loop_does_not_step():
    world, clock = CountingWorld(), FakeClock()
    loop = SimulationLoop(world, real_time_factor=0.0, paused=True, clock=clock)
    loop.run_once()
    assert world.iterations == 0
    loop.set_paused(False)
    loop.run_once()
    assert world.iterations > 0


def test_jobs_run_in_the_loop_thread_and_return_values():
    world = CountingWorld()
    loop = SimulationLoop(world, real_time_factor=0.0, paused=True)
    loop.start()
    try:
        name = loop.call(lambda: threading.current_thread().name)
        assert name == "simulation_loop"
        assert loop.call(lambda: world.step(5) or world.iterations) == 5
        with pytest.raises(KeyError):
            loop.call(lambda: {}["missing"])
        loop.set_paused(False)
        assert loop.call(lambda: world.iterations, timeout=5) >= 5
        assert world.step_threads == {"simulation_loop"}
    finally:
        loop.stop()


def test_step_error_pauses_and_is_reported():
    world = CountingWorld(fail_at=30)
    errors = []
    loop = SimulationLoop(world, real_time_factor=0.0, batch=10, on_error=errors.append)
    for _ in range(5):
        loop.run_once()
    assert loop.paused and world.iterations == 30
    assert len(errors) == 1 and "boom" in str(errors[0])


def test_measured_rtf_is_reported():
    world, clock = CountingWorld(), FakeClock()
    seen = []
    loop = SimulationLoop(world, real_time_factor=0.5, clock=clock, batch=1000, rtf_period=1.0,
                          on_rtf=lambda rtf, t: seen.append(rtf))
    for _ in range(300):
        clock.t += 0.01
        loop.run_once()
    assert seen and seen[-1] == pytest.approx(0.5, abs=0.05)


def test_stopped_loop_refuses_calls():
    loop = SimulationLoop(CountingWorld(), paused=True)
    loop.start()
    loop.stop()
    with pytest.raises(SimulationError):
        loop.call(lambda: 1)


def test_call_made_before_start_waits_for_the_loop():
    """Services are advertised before the loop thread starts: an early request must be served
    by the loop once it runs, never refused as 'shutting down' nor run in the caller's thread."""
    world = CountingWorld()
    loop = SimulationLoop(world, real_time_factor=0.0, paused=True)
    answer = {}
    caller = threading.Thread(target=lambda: answer.setdefault(
        "thread", loop.call(lambda: threading.current_thread().name, timeout=10)))
    caller.start()
    loop.start()
    try:
        caller.join(10)
        assert answer.get("thread") == "simulation_loop"
    finally:
        loop.stop()
