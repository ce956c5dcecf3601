"""Shared helpers of the simulator's rostest nodes (sim_*.py): service proxies with Gazebo's types,
fixtures, waiting on conditions with wall-clock timeouts."""
import os
import time

import rospy
from gazebo_msgs import srv as gzs
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import Pose
from std_srvs.srv import Empty

from modrob_msgs.srv import StepSimulation
from modrob_sim.waits import Latest, wait_until  # noqa: F401 - the checks import Latest from here

FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sim")

SERVICES = {
    "spawn_urdf_model": gzs.SpawnModel, "spawn_sdf_model": gzs.SpawnModel,
    "delete_model": gzs.DeleteModel, "get_model_state": gzs.GetModelState,
    "set_model_state": gzs.SetModelState, "set_model_configuration": gzs.SetModelConfiguration,
    "get_link_state": gzs.GetLinkState, "set_link_state": gzs.SetLinkState,
    "get_world_properties": gzs.GetWorldProperties, "get_model_properties": gzs.GetModelProperties,
    "get_joint_properties": gzs.GetJointProperties, "get_link_properties": gzs.GetLinkProperties,
    "set_link_properties": gzs.SetLinkProperties,
    "apply_body_wrench": gzs.ApplyBodyWrench, "apply_joint_effort": gzs.ApplyJointEffort,
    "clear_body_wrenches": gzs.BodyRequest, "clear_joint_forces": gzs.JointRequest,
    "pause_physics": Empty, "unpause_physics": Empty, "reset_simulation": Empty, "reset_world": Empty,
    "get_physics_properties": gzs.GetPhysicsProperties, "set_physics_properties": gzs.SetPhysicsProperties,
    "step": StepSimulation,
}


def fixture(name):
    with open(os.path.join(FIXTURES, name)) as f:
        return f.read()


class Gazebo(object):
    """Proxies for every /gazebo service: ``gz.get_model_state(...)``."""

    def __init__(self, ns="/gazebo", timeout=60.0):
        deadline = time.time() + timeout
        for name in SERVICES:
            rospy.wait_for_service("%s/%s" % (ns, name), timeout=max(1.0, deadline - time.time()))
        for name, typ in SERVICES.items():
            setattr(self, name, rospy.ServiceProxy("%s/%s" % (ns, name), typ))

    def spawn(self, name, urdf_file, x=0.0, y=0.0, z=0.0, qz=0.0, qw=1.0, ns="", frame=""):
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = x, y, z
        pose.orientation.z, pose.orientation.w = qz, qw
        return self.spawn_urdf_model(model_name=name, model_xml=fixture(urdf_file), robot_namespace=ns,
                                     initial_pose=pose, reference_frame=frame)

    def sim_time(self):
        return self.get_world_properties().sim_time

    def iterations(self):
        return self.step(steps=0).iterations


def model_names():
    latest = Latest("/gazebo/model_states", ModelStates)
    wait_until(lambda: latest.get() is not None, 10.0)
    msg = latest.get()
    latest.sub.unregister()
    return list(msg.name) if msg else None
