"""The World's simulated time stays on the nanosecond grid of its steps, as Gazebo's common::Time
(whole seconds and nanoseconds) adds them: summed in doubles, 1 ms steps come off the grid by a
nanosecond at step 180963 (a /clock stamp of 180.963000001 s; the /clock rostest saw one). Native
stretches (mr_run_steps) and Python steps give the same times, bit for bit."""
import pytest

from modrob_sim import physics
from modrob_sim.physics import native as native_mod
from modrob_sim.physics.world import next_time

needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")

#: the first step at which a plain float sum of 1 ms steps rounds to another nanosecond
OFF_GRID_STEP = 180963


def test_a_float_sum_leaves_the_grid_where_next_time_does_not():
    t = s = 0.0
    for k in range(1, OFF_GRID_STEP + 1):
        t, s = next_time(t, 0.001), s + 0.001
    assert round(s * 1e9) != OFF_GRID_STEP * 10 ** 6       # the plain sum: a nanosecond off
    assert round(t * 1e9) == OFF_GRID_STEP * 10 ** 6
    assert t == OFF_GRID_STEP / 1000.0                    # the nearest double to it, exactly


def test_a_step_that_is_no_whole_nanosecond_rounds_each_step():
    # a time that keeps whole nanoseconds: a step of 1/3 ms advances it by 333333 ns each time
    t, times = 0.0, []
    for _ in range(3):
        t = next_time(t, 1.0 / 3000.0)
        times.append(t)
    assert [round(x * 1e9) for x in times] == [333333, 666666, 999999]
    assert times == [x / 1e9 for x in (333333, 666666, 999999)]


@needs_c
def test_native_stretches_and_python_steps_keep_the_same_grid():
    """The native World's time after a long run of empty steps is on the grid; the pure backend's
    Python steps give the same time for the same steps."""
    native = physics.World(time_step=0.001, native=True)
    n = OFF_GRID_STEP + 100
    native.step(n)
    assert native.native_steps > n - 10          # the steps were made in C
    assert round(native.time * 1e9) == n * 10 ** 6 and native.time == n / 1000.0
    pure = physics.World(time_step=0.001, native=False)
    pure.step(2000)
    native2 = physics.World(time_step=0.001, native=True)
    native2.step(2000)
    assert pure.time == native2.time == 2.0
