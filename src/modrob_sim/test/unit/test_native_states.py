"""The /gazebo node's model and link states serialised by the C loop (gazebo_ros.native_states) are
byte for byte what rospy serialises from the messages the Python path builds (Link.pose,
Link.twist): a world-attached arm moving under efforts, welded links (link frame away from the
body's), a tumbling free body, a static model that is moved, a model spawned after the first
message and one removed."""
import io
import os

import pytest

physics = pytest.importorskip("modrob_sim.physics")
from modrob_sim.gazebo_ros import native_states  # noqa: E402
from modrob_sim.gazebo_ros.state_publishers import link_states_msg, model_states_msg  # noqa: E402

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")

BOX = """<robot name="box">
  <link name="body">
    <inertial><origin xyz="0.05 -0.02 0.03" rpy="0.3 0.1 -0.2"/><mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial>
    <collision><geometry><box size="0.2 0.1 0.1"/></geometry></collision>
  </link>
  <joint name="weld" type="fixed"><parent link="body"/><child link="nose"/>
    <origin xyz="0.15 0.02 -0.01" rpy="0.2 -0.4 0.9"/></joint>
  <link name="nose">
    <inertial><origin xyz="0.01 0 0"/><mass value="0.3"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
    <collision><geometry><sphere radius="0.03"/></geometry></collision>
  </link>
</robot>"""

TABLE = """<robot name="table"><link name="top">
  <collision><geometry><box size="1 1 0.05"/></geometry></collision></link>
  <gazebo><static>true</static></gazebo></robot>"""


def rospy_bytes(msg):
    from rospy.msg import serialize_message
    b = io.BytesIO()
    serialize_message(b, 1, msg)
    return b.getvalue()[4:]


def check(world, ms, ls):
    assert ms.serialized() == rospy_bytes(model_states_msg(world))
    assert ls.serialized() == rospy_bytes(link_states_msg(world))


@pytest.mark.skipif(not native_states.available(physics.World()), reason="needs the C loop")
def test_native_states_are_rospys_bytes():
    w = physics.World(time_step=0.001)
    w.add_urdf("table", TABLE, pose=((0.0, 0.0, 0.4), (0.0, 0.0, 0.0, 1.0)))
    with open(os.path.join(FIX, "arm_3dof.urdf")) as f:
        arm = w.add_urdf("arm", f.read().replace("PositionJointInterface", "EffortJointInterface"))
    box = w.add_urdf("box", BOX, pose=((0.3, 0.9, 1.2), (0.1, 0.2, 0.3, 0.9273618495495703)))
    box.set_twist(((0.4, -0.3, 1.5), (2.0, -1.0, 3.5)))
    version = w.layout_version
    ms, ls = native_states.model_states(w), native_states.link_states(w)
    check(w, ms, ls)
    efforts = {"yaw": 3.0, "shoulder": -8.0, "elbow": 2.5}
    for k in range(300):
        for name, f in efforts.items():
            arm.joints[name].set_effort(f * (1 if (k // 50) % 2 == 0 else -1))
        w.step(1)
        if k % 37 == 0:
            check(w, ms, ls)
    assert any(abs(v) > 1e-3 for v in box.twist[1])
    # a static model moved: its static pose is re-read
    w.models["table"].set_pose(((0.5, -0.2, 0.3), (0.0, 0.0, 0.38941834230865047, 0.9210609940028851)))
    check(w, ms, ls)
    # the layout changes with a spawn and a removal (the node builds new messages then)
    w.add_urdf("box2", BOX.replace('name="box"', 'name="box2"'), pose=((-0.5, 0.2, 0.8), (0, 0, 0, 1)))
    assert w.layout_version != version
    ms, ls = native_states.model_states(w), native_states.link_states(w)
    w.step(20)
    check(w, ms, ls)
    w.remove_model("box")
    ms, ls = native_states.model_states(w), native_states.link_states(w)
    w.step(5)
    check(w, ms, ls)
