"""When the node's ~model_states and ~link_states go out (StatePublishers.after_step/after_due, the
node's after-step hook in the World): once per period of ``~publish_rate``, at the first step of the
period at which the World stops anyway (a sensor's sample, a controller's update), else at the
period's last step. A sensor at the states' rate on another phase (an IMU counts its period from its
first step) then makes the World stop once per period, not twice."""
import math
import os

import pytest
import rospy

from modrob_sim.gazebo_ros import state_publishers
from modrob_sim.gazebo_ros.node_params import Params
from modrob_sim.physics import World

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "physics")


class StampingPublisher(object):
    """Takes what is published, with the World's time then; one subscriber."""
    world = None

    def __init__(self, topic, msg_class, queue_size=1, latch=False, **kw):
        self.topic, self.times, self.sent = topic, [], []

    def get_num_connections(self):
        return 1

    def publish(self, msg):
        self.sent.append(msg)
        self.times.append(round(StampingPublisher.world.time, 6))

    def unregister(self):
        pass


class Sensor(object):
    """A sensor's after-hook: samples every ``period`` from ``first`` (its first step), as the
    plugins' RateGate; records the steps it was called at."""

    def __init__(self, world, first, period):
        self.world, self.next, self.period, self.calls = world, first, period, []

    def after(self, t, dt):
        self.calls.append(round(t, 6))
        if t + 0.5 * dt >= self.next:
            self.next += self.period

    def due(self):
        return self.next - 0.5 * self.world.time_step


def _node(monkeypatch, sensor_first=None):
    monkeypatch.setattr(rospy, "Publisher", StampingPublisher)
    monkeypatch.setattr(state_publishers, "publisher", StampingPublisher)
    world = World()
    StampingPublisher.world = world
    with open(os.path.join(FIX, "box.urdf")) as f:
        world.add_urdf("box", f.read(), pose=((0.0, 0.0, 0.5), (0.0, 0.0, 0.0, 1.0)))
    params = Params()
    params.marker_rate = 0.0
    sp = state_publishers.StatePublishers(world, params)
    sensor = None
    if sensor_first is not None:
        sensor = Sensor(world, sensor_first, 1.0 / params.publish_rate)

    def after(t, dt):                       # as the node's hook: the plugins, then the publishers
        if sensor is not None:
            sensor.after(t, dt)
        sp.after_step()

    def due():
        d = sp.after_due()
        return d if sensor is None else min(d, sensor.due())
    world.add_step_hook(after=after, after_due=due)
    return world, sp, sensor


@pytest.mark.parametrize("phase", [0.003, 0.007])
def test_the_states_ride_on_a_sensor_of_their_rate_on_another_phase(monkeypatch, phase):
    world, sp, imu = _node(monkeypatch, sensor_first=0.5 + phase)
    world.step(500)
    del imu.calls[:], sp._model_states_pub.times[:], sp._link_states_pub.times[:]
    world.step(1000)
    period = 1.0 / Params().publish_rate
    times = sp._model_states_pub.times
    # one message per period of the grid, and the World stopped only for the sensor's samples
    assert len(times) == 100
    assert sorted(set(math.floor(t / period + 1e-6) for t in times)) == \
        list(range(int(round(0.5 / period)), int(round(1.5 / period))))
    assert set(imu.calls) >= set(times)
    assert len(imu.calls) == 100
    assert all(abs((t - phase) / period - round((t - phase) / period)) < 1e-3 for t in imu.calls)
    assert len(sp._link_states_pub.times) == 100


def test_alone_the_states_go_out_at_each_periods_last_step(monkeypatch):
    world, sp, _ = _node(monkeypatch)
    world.step(500)
    del sp._model_states_pub.times[:]
    world.step(100)
    period = 1.0 / Params().publish_rate
    times = sp._model_states_pub.times
    assert len(times) == 10
    step = world.time_step
    assert all(abs((t + step) / period - round((t + step) / period)) < 1e-3 for t in times), times
    # the World made no other stop: every other step of the 100 was native
    assert world.native_steps + world.hooked_steps == world.iterations
