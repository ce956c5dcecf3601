"""Due times (docs/plugins.md): a plugin that says when its hook next has work is called at that
step, and the node steps natively in between; the sensor plugins' readings, the robot's controllers
and the world's state are then bit for bit those of stepping every step in Python. A hook without
a due time keeps every step in Python, as before."""
import math
import os

import pytest

from modrob_sim.gazebo_ros import plugins
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin, RateGate, SensorPlugin
from modrob_sim.gazebo_ros.plugin_host import PluginHost
from modrob_sim.gazebo_ros.testing import ControlRig
from modrob_sim.physics import native as native_mod
from modrob_sim.ros_control.manager import STRICT

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")
SENSORS = """
  <gazebo reference="l3"><sensor type="imu" name="imu"><update_rate>200</update_rate>
    <plugin name="imu" filename="libtest_due_sensor.so"/></sensor></gazebo>
  <gazebo reference="base"><sensor type="ray" name="scan"><update_rate>40</update_rate>
    <plugin name="scan" filename="libtest_due_sensor.so"/></sensor></gazebo>
  <gazebo><plugin name="probe" filename="libtest_due_probe.so"><rate>30</rate></plugin></gazebo>
</robot>"""
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


class Sensor(SensorPlugin):
    """A sensor at its <update_rate>: the link's pose and twist (SensorPlugin's own due time)."""

    def load(self, model, spec, context):
        self.readings = []

    def sense(self, t):
        self.readings.append((t, self.link.pose, self.link.twist))


class Probe(ModelPlugin):
    """A model plugin with a rate of its own, declared through its gate."""

    def load(self, model, spec, context):
        self.gate = RateGate(self.param("rate", cast=float))
        self.samples = []

    def after_step(self, t, dt):
        if self.gate.due(t):
            self.samples.append((t, [j.position for j in self.model.joints_in_order]))

    def after_due(self):
        return self.gate.next_time


class Undeclared(Probe):
    calls = 0

    def after_step(self, t, dt):
        Undeclared.calls += 1
        Probe.after_step(self, t, dt)

    def after_due(self):
        return ModelPlugin.after_due(self)


@pytest.fixture(autouse=True)
def registered():
    plugins.register_plugin("libtest_due_sensor.so", Sensor)
    plugins.register_plugin("libtest_due_probe.so", Probe)
    yield
    plugins.unregister_plugin("libtest_due_sensor.so")
    plugins.unregister_plugin("libtest_due_probe.so")


class Rig(ControlRig):
    def __init__(self, fast):
        with open(os.path.join(FIX, "arm_3dof.urdf")) as f:
            xml = f.read().replace("PositionJointInterface", "EffortJointInterface")
        super(Rig, self).__init__(xml.replace("</robot>", SENSORS))
        self.ctl = {"jsc": self.joint_state_controller(publish_rate=50)}
        for j, (p, d) in (("yaw", (80.0, 4.0)), ("shoulder", (200.0, 10.0)), ("elbow", (100.0, 5.0))):
            self.ctl[j] = self.mgr.load(j, {"type": "effort_controllers/JointPositionController", "joint": j,
                                            "pid": {"p": p, "i": 20.0, "d": d, "i_clamp": 5.0}})
            self.ctl[j].state_wanted = lambda: False        # nobody subscribed to their states
            self.adapter(j)
        assert self.mgr.switch(list(self.ctl), [], STRICT)[0]
        self.host = PluginHost(self.world, "/gazebo", lambda uri: uri)
        self.loaded = self.host.load(self.model, "/arm")
        self.start(fast, plugins=self.host)

    def outputs(self):
        return [getattr(p, "readings", None) or p.samples for p in self.loaded]


def run(fast, steps=1500):
    rig = Rig(fast)
    while rig.world.iterations < steps:
        i = rig.world.iterations
        if i == 300:
            rig.ctl["yaw"].set_command(1.0)
            rig.ctl["elbow"].set_command(-1.2)
        rig.step(min(10, 300 - i) if i < 300 else 10)
    return rig


def test_declared_due_times():
    rig = Rig(False)
    imu, scan, probe = rig.loaded
    assert math.isinf(rig.host.after_due()) and rig.host.after_due() < 0     # nothing sensed yet: now
    rig.step(1)
    assert imu.after_due() == pytest.approx(0.001 + 0.005)
    assert scan.after_due() == pytest.approx(0.001 + 0.025)
    assert probe.after_due() == pytest.approx(0.001 + 1 / 30.0)
    assert rig.host.after_due() == imu.after_due()
    assert rig.host.before_due() == float("inf")      # no before hook among these plugins


def test_a_sensor_plugin_without_sense_has_no_step_work():
    class Quiet(SensorPlugin):
        pass
    plugins.register_plugin("libtest_due_sensor.so", Quiet)
    rig = Rig(False)
    assert all(p.after_due() == float("inf") for p in rig.loaded[:2])


@needs_c
def test_sensors_with_due_times_step_natively_and_read_what_python_steps_read():
    ref, fast = run(False), run(True)
    assert len(ref.outputs()[0]) >= 1500 // 5 and len(ref.outputs()[1]) >= 1500 // 25
    assert ref.outputs() == fast.outputs()
    assert ref.log == fast.log and len(fast.log) > 20
    assert ref.world.state_digest() == fast.world.state_digest()
    assert abs(fast.model.joints["yaw"].position - 1.0) < 0.05
    # the 200 Hz IMU ends a batch every 5 steps: the steps run in C, the 300 readings in Python;
    # the controllers' updates in Python: the joint_states samples (50 Hz) and the new commands
    assert fast.world.native_steps >= 0.95 * fast.world.iterations, "%d of %d steps in batches" % (
        fast.world.native_steps, fast.world.iterations)


@needs_c
def test_a_hook_without_a_due_time_runs_at_every_step():
    plugins.register_plugin("libtest_due_probe.so", Undeclared)
    Undeclared.calls = 0
    fast = run(True, steps=200)
    assert Undeclared.calls == fast.world.iterations == 200
    # each step is made in C and its after-hooks run in Python
    assert len(fast.loaded[2].samples) == 6            # its own gate still decimates (30 Hz, 0.2 s)


REAL_SENSORS = """
  <gazebo reference="l3"><sensor type="imu" name="imu"><always_on>true</always_on>
    <update_rate>200</update_rate>
    <plugin name="imu" filename="libgazebo_ros_imu_sensor.so"><topicName>imu</topicName>
    <updateRateHZ>200</updateRateHZ></plugin></sensor></gazebo>
  <gazebo reference="base"><sensor type="ray" name="scan"><update_rate>40</update_rate>
    <ray><scan><horizontal><samples>36</samples><min_angle>-3.14</min_angle><max_angle>3.14</max_angle>
    </horizontal></scan><range><min>0.1</min><max>5</max></range></ray>
    <plugin name="scan" filename="libgazebo_ros_laser.so"><topicName>scan</topicName></plugin>
  </sensor></gazebo>
</robot>"""


class _Listened(object):
    """A publisher whose subscribers come and go with ``listening[0]``; keeps what it sends."""

    def __init__(self, topic, listening):
        self.name, self.listening, self.sent = topic, listening, []

    @property
    def has_subscribers(self):
        return self.listening[0]

    def publish(self, msg):
        self.sent.append(msg)

    def publish_later(self, build):
        self.sent.append(build())

    def unregister(self):
        pass


class SensorArm(ControlRig):
    """The arm moving (a commanded yaw) with the real IMU (200 Hz) and laser (40 Hz) plugins, their
    subscribers present while ``listening[0]``."""

    def __init__(self, fast):
        import modrob_sim.sensors.ros_plugins  # noqa: F401 - registers the sensor plugins
        with open(os.path.join(FIX, "arm_3dof.urdf")) as f:
            xml = f.read().replace("PositionJointInterface", "EffortJointInterface")
        super(SensorArm, self).__init__(xml.replace("</robot>", REAL_SENSORS))
        self.listening = [True]
        self.pubs = {}

        def advertise(topic, msg_class, queue_size=1, latch=False):
            return self.pubs.setdefault(topic, _Listened(topic, self.listening))
        c = self.mgr.load("yaw", {"type": "effort_controllers/JointPositionController", "joint": "yaw",
                                  "pid": {"p": 80.0, "d": 4.0}})
        c.state_wanted = lambda: False
        self.adapter("yaw")
        assert self.mgr.switch(["yaw"], [], STRICT)[0]
        c.set_command(2.0)
        self.host = PluginHost(self.world, "/gazebo", lambda uri: uri, advertise=advertise)
        self.host.load(self.model, "/arm")
        self.start(fast, plugins=self.host)

    def sent(self, topic):
        key = [k for k in self.pubs if k.endswith(topic)][0]
        out = []
        for m in self.pubs[key].sent:
            fields = (m.linear_acceleration, m.angular_velocity, m.orientation) if topic == "imu" else \
                (list(m.ranges),)
            out.append((m.header.stamp.to_sec(), str(fields)))
        return out


@needs_c
def test_sensors_nobody_listens_to_step_natively_and_send_what_they_would_have_sent(monkeypatch):
    """While no subscriber listens, the laser and the (noiseless) IMU take no readings: their
    hooks are due only at a look every IDLE_LOOK s, so the World steps natively through their
    update times. Once someone listens they send what sensors that never idled send, from at most
    IDLE_LOOK (and one IMU update) after the subscriber came."""
    from modrob_sim.sensors import ros_plugins
    from modrob_sim.physics.due import IDLE_LOOK
    calls = []
    for cls in (ros_plugins.ImuSensorPlugin, ros_plugins.LaserPlugin):
        def counted(self, t, dt, _hook=cls.after_step):
            calls.append(t)
            return _hook(self, t, dt)
        monkeypatch.setattr(cls, "after_step", counted)
    always = SensorArm(True)
    always.step(1500)
    come_and_go = SensorArm(True)
    come_and_go.listening[0] = False
    del calls[:]
    come_and_go.step(500)
    # the sensors' hooks ran at the first readings and at a look every IDLE_LOOK each (not at the
    # IMU's 100 and the laser's 20 update times); every step but the first update's was native
    assert len(calls) <= 2 * (0.5 / IDLE_LOOK + 1), calls
    assert come_and_go.world.native_steps >= 498
    come_and_go.listening[0] = True
    come_and_go.step(500)
    come_and_go.listening[0] = False
    come_and_go.step(500)
    assert always.world.state_digest() == come_and_go.world.state_digest()
    for topic, period in (("imu", 0.005), ("scan", 0.025)):
        got, ref = come_and_go.sent(topic), always.sent(topic)
        assert got, topic
        first, last = got[0][0], got[-1][0]
        assert 0.5 <= first <= 0.5 + IDLE_LOOK + 2 * period + 1e-9, (topic, first)
        assert last >= 1.0 - period - 1e-9, (topic, last)
        assert got == [r for r in ref if first - 1e-9 <= r[0] <= last + 1e-9], topic
