"""Tier 1: force/torque sensing on a joint (gazebo_ros_ft_sensor, <sensor type="force_torque">)
on both physics backends: the weight of a known mass and its moment, the effort a held joint
carries, Gazebo's frames and directions, and what cannot be measured."""
import math
import os

import pytest

from modrob_sim.physics import World
from modrob_sim.physics.actuators import POSITION_PID, PidGains
from modrob_sim.physics.transforms import quat_conj, quat_from_rpy, quat_rotate
from modrob_sim.sensors.errors import SensorConfigError
from modrob_sim.sensors.force_torque import JointWrench

FIXTURE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "force",
                       "ft_arm.urdf")
M, G, ARM = 2.0, 9.81, 0.1           # the fixture's load: 2 kg, centre of mass 0.1 m out along x
BACKENDS = [None, False]             # the C loop (default) and the pure-Python path


def ft_arm(native, axis="0 0 1"):
    with open(FIXTURE) as f:
        urdf = f.read()
    w = World(native=native)
    m = w.add_urdf("ft_arm", urdf.replace('<axis xyz="0 0 1"/>', '<axis xyz="%s"/>' % axis))
    return w, m


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


@pytest.mark.parametrize("native", BACKENDS)
def test_a_hanging_mass_reads_its_weight_and_moment_in_the_child_frame(native):
    w, m = ft_arm(native)
    ft = JointWrench(m.joints["wrist"], "test")
    assert ft.read() == ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))      # nothing before the first step
    w.step(200)
    f, t = ft.read()
    # child_to_parent: the load pushes down on the post with its weight, and its weight's moment
    # about the joint, r x F with r = (0.1, 0, 0) in the child frame
    assert f[2] == pytest.approx(-M * G, rel=0.01)
    assert abs(f[0]) < 0.01 * M * G and abs(f[1]) < 0.01 * M * G
    assert t[1] == pytest.approx(ARM * M * G, rel=0.01)
    assert abs(t[0]) < 0.01 and abs(t[2]) < 0.01


@pytest.mark.parametrize("native", BACKENDS)
def test_a_held_horizontal_joint_carries_the_effort_that_holds_it(native):
    # axis y: gravity turns the load about the joint; a PID actuator holds it at 0. ODE's
    # constraint rows carry the weight, the applied effort carries the moment about the axis
    w, m = ft_arm(native, axis="0 1 0")
    j = m.joints["wrist"]
    a = w.add_actuator(j, POSITION_PID, gains=PidGains(500.0, 0.0, 3.0, 0.0, 0.0))
    a.command = 0.0
    ft = JointWrench(j, "test")
    w.step(1500)
    assert abs(j.position) < 0.01 and abs(j.velocity) < 1e-3
    f, t = ft.read()
    # the child frame is the joint frame turned by the (small) joint angle about y
    c = math.cos(j.position)
    assert f[2] == pytest.approx(-M * G * c, rel=0.01)
    assert t[1] == pytest.approx(ARM * M * G * c, rel=0.01)
    assert a.last.applied == pytest.approx(-ARM * M * G * c, rel=0.02)   # the motor lifts the load


@pytest.mark.parametrize("native", BACKENDS)
def test_frames_and_directions_as_gazebo_documents(native):
    w, m = ft_arm(native)
    j = m.joints["wrist"]
    sensor_pose = ((0.0, 0.0, 0.0), quat_from_rpy(0.0, 0.0, math.pi / 2))
    child = JointWrench(j, "test", "child", "child_to_parent")
    to_child = JointWrench(j, "test", "child", "parent_to_child")
    parent = JointWrench(j, "test", "parent", "parent_to_child")
    sensor = JointWrench(j, "test", "sensor", "child_to_parent", sensor_pose)
    w.step(200)
    f, t = child.read()
    f2, t2 = to_child.read()
    assert close(f2, [-x for x in f], 1e-9) and close(t2, [-x for x in t], 1e-9)
    # the parent (the post) is level; the child turned by the joint's rpy yaw 0.5 about z
    fp, tp = parent.read()
    assert fp[2] == pytest.approx(M * G, rel=0.01)
    q = m.links["load"].pose[1]
    assert close(tp, quat_rotate(q, t2), 1e-6)
    # the sensor frame is the child's turned by +90 degrees about z: x_sensor = y_child
    fs, ts = sensor.read()
    assert close(fs, quat_rotate(quat_conj(sensor_pose[1]), f), 1e-9)
    assert ts[0] == pytest.approx(t[1], rel=1e-9) and ts[1] == pytest.approx(-t[0], abs=1e-9)


def test_what_cannot_be_measured_is_refused_with_the_reason():
    w, m = ft_arm(None)
    with pytest.raises(SensorConfigError, match="joint 'anchor' is fixed.*revolute or prismatic"):
        JointWrench(m.joints["anchor"], "model 'ft_arm' plugin libgazebo_ros_ft_sensor.so")
    with pytest.raises(SensorConfigError, match="<frame> 'tool' is not one of child, parent, sensor"):
        JointWrench(m.joints["wrist"], "x", frame="tool")
    with pytest.raises(SensorConfigError, match="<measure_direction> 'up'"):
        JointWrench(m.joints["wrist"], "x", direction="up")


class FakePub(object):
    """Stands in for context.advertise's PluginPublisher: records what is published."""

    def __init__(self, topic):
        self.name = topic
        self.has_subscribers = True
        self.sent = []

    def publish(self, msg):
        self.sent.append(msg)

    def unregister(self):
        pass


@pytest.mark.parametrize("native", BACKENDS)
def test_the_plugins_publish_at_their_rates_and_the_physics_steps_natively_between(native):
    pubs = {}

    def advertise(topic, msg_class, queue_size=1, latch=False):
        pubs[topic] = FakePub(topic)
        return pubs[topic]
    import modrob_sim.sensors.ros_plugins  # noqa: F401 (registers the plugin file names)
    from modrob_sim.gazebo_ros.plugin_host import PluginHost
    with open(FIXTURE) as f:
        urdf = f.read()
    w = World(native=native)
    host = PluginHost(w, "/gazebo", lambda uri: uri, advertise=advertise)
    w.add_step_hook(host.before_step, host.after_step, host.before_due, host.after_due)   # as the node
    model, sensor = host.load(w.add_urdf("ft_arm", urdf))
    w.step(1000)                                   # 1 s: gazebo_ros_ft_sensor at 100 Hz, the sensor at 50
    ft, wrist = pubs["/ft_sensor"].sent, pubs["/wrist_ft"].sent
    assert len(ft) == 100 and len(wrist) == 50
    m = ft[-1]
    assert m.header.frame_id == "load" and m.header.stamp.to_sec() == pytest.approx(0.991)
    assert m.wrench.force.z == pytest.approx(-M * G, rel=0.01)
    assert m.wrench.torque.y == pytest.approx(ARM * M * G, rel=0.01)
    assert wrist[-1].header.frame_id == "post" and wrist[-1].wrench.force.z == pytest.approx(M * G, rel=0.01)
    if w.native:
        # between the samples nothing of the plugins runs: the C loop makes the steps
        assert w.native_steps >= 0.95 * w.iterations, "%d of %d" % (w.native_steps, w.iterations)
    w.close()


SDF_ARM = """<sdf version="1.6"><model name="sdf_arm">
  <link name="post"><pose>0 0 0.3 0 0 0</pose>
    <inertial><mass>5</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz></inertia></inertial></link>
  <joint name="anchor" type="fixed"><parent>world</parent><child>post</child></joint>
  <link name="load"><pose>0 0 0.6 0 0 0</pose>
    <inertial><pose>0.1 0 0 0 0 0</pose><mass>2</mass>
      <inertia><ixx>0.002</ixx><iyy>0.002</iyy><izz>0.002</izz></inertia></inertial></link>
  <joint name="wrist" type="revolute"><parent>post</parent><child>load</child>
    <axis><xyz>0 0 1</xyz><limit><lower>-1.5</lower><upper>1.5</upper></limit></axis>
    <sensor name="wrist_ft" type="force_torque"><update_rate>100</update_rate>
      <force_torque><frame>child</frame><measure_direction>parent_to_child</measure_direction></force_torque>
      <plugin name="ft" filename="libgazebo_ros_ft_sensor.so"><topicName>sdf_ft</topicName></plugin>
    </sensor>
  </joint>
</model></sdf>"""


def test_a_force_torque_sensor_on_an_sdf_joint():
    pubs = {}

    def advertise(topic, msg_class, queue_size=1, latch=False):
        pubs[topic] = FakePub(topic)
        return pubs[topic]
    import modrob_sim.sensors.ros_plugins  # noqa: F401 (registers the plugin file names)
    from modrob_sim.gazebo_ros.plugin_host import PluginHost
    w = World()
    host = PluginHost(w, "/gazebo", lambda uri: uri, advertise=advertise)
    w.add_step_hook(host.before_step, host.after_step, host.before_due, host.after_due)
    (m,) = w.add_sdf(SDF_ARM)
    (ft,) = host.load(m)
    w.step(200)
    msg = pubs["/sdf_ft"].sent[-1]
    assert len(pubs["/sdf_ft"].sent) == 20 and msg.header.frame_id == "load"
    assert msg.wrench.force.z == pytest.approx(M * G, rel=0.01)                 # parent_to_child: up
    assert msg.wrench.torque.y == pytest.approx(-ARM * M * G, rel=0.01)
    w.close()
