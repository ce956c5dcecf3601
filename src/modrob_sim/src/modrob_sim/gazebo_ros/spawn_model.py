"""The logic of the ``spawn_model`` script: gazebo_ros's command line, the same flags and exit codes
(0 spawned, 1 failed with a message saying why)."""
import argparse
import os
import sys
import time
import xml.etree.ElementTree as ET

import rospy
from gazebo_msgs.msg import ModelStates
from gazebo_msgs.srv import DeleteModel, SetModelConfiguration, SpawnModel
from geometry_msgs.msg import Pose
from std_srvs.srv import Empty

from modrob_sim.gazebo_ros.transforms import quat_from_rpy

DATABASE_TEMPLATE = """<sdf version="1.6">
  <world name="default">
    <include>
      <uri>model://{}</uri>
    </include>
  </world>
</sdf>"""


def build_parser(default_namespace="/"):
    p = argparse.ArgumentParser(prog="spawn_model",
                                description="Spawn a model in the simulator using Gazebo's ROS API")
    fmt = p.add_mutually_exclusive_group(required=True)
    fmt.add_argument("-urdf", action="store_true", help="Incoming xml is in urdf format")
    fmt.add_argument("-sdf", action="store_true", help="Incoming xml is in sdf format")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("-file", metavar="FILE_NAME", help="Load model xml from file")
    src.add_argument("-param", metavar="PARAM_NAME", help="Load model xml from ROS parameter")
    src.add_argument("-database", metavar="MODEL_NAME",
                     help="Load model XML of a model in GAZEBO_MODEL_PATH (model://MODEL_NAME)")
    src.add_argument("-stdin", action="store_true", help="Load model from stdin")
    p.add_argument("-model", required=True, metavar="MODEL_NAME", help="Name of model to spawn")
    p.add_argument("-reference_frame", default="",
                   help='Name of the model/body where initial pose is defined. If left empty or specified as '
                        '"world", the world frame is used')
    p.add_argument("-gazebo_namespace", default="/gazebo",
                   help="ROS namespace of the simulator's ROS interfaces. Defaults to /gazebo/")
    p.add_argument("-robot_namespace", default=default_namespace,
                   help="change ROS namespace of gazebo-plugins")
    p.add_argument("-unpause", action="store_true", help="unpause physics after spawning model")
    p.add_argument("-wait", metavar="MODEL_NAME", help="wait for model to exist")
    for axis, what in (("x", "x component of initial position, meters"), ("y", "y component of initial "
                       "position, meters"), ("z", "z component of initial position, meters"),
                       ("R", "roll angle of initial orientation, radians"),
                       ("P", "pitch angle of initial orientation, radians"),
                       ("Y", "yaw angle of initial orientation, radians")):
        p.add_argument("-" + axis, type=float, default=0.0, help=what)
    p.add_argument("-J", dest="joints", default=[], action="append", metavar=("JOINT_NAME", "JOINT_POSITION"),
                   nargs=2, help="initialize the specified joint at the specified position")
    p.add_argument("-package_to_model", action="store_true",
                   help='convert urdf <mesh filename="package://..." to <mesh filename="model://..."')
    p.add_argument("-b", dest="bond", action="store_true",
                   help="bond to the simulator and delete the model when this program is interrupted")
    p.add_argument("-timeout", type=float, default=0.0,
                   help="seconds to wait for the simulator's services "
                        "(default 0: wait forever, as gazebo_ros)")
    return p


class SpawnModelCommand(object):
    """``SpawnModelCommand(argv).run()`` -> exit code. Errors are logged with rospy.logerr."""

    def __init__(self, argv, default_namespace="/"):
        self.args = build_parser(default_namespace).parse_args(argv)
        joints = []
        for name, value in self.args.joints:
            try:
                joints.append((name, float(value)))
            except ValueError:
                raise SystemExit("spawn_model: -J %s %s: the position must be a number" % (name, value))
        self.args.joints = joints
        self.ns = self.args.gazebo_namespace.rstrip("/")
        self._xml = None

    def prepare(self):
        """Read and check a -file or -stdin model before any ROS connection, so that a bad file
        fails at once even without a master. Returns an error text or None."""
        if self.args.file or self.args.stdin:
            text, err = self.load_xml()
            if err:
                return err
            try:
                ET.fromstring(text)
            except ET.ParseError as exc:
                return "invalid XML in %s: %s" % (self.args.file or "stdin", exc)
            self._xml = text
        return None

    def fail(self, text):
        rospy.logerr("spawn_model: %s" % text)
        return 1

    def load_xml(self):
        """(xml text, None) or (None, error text)."""
        a = self.args
        if a.file:
            if not os.path.exists(a.file):
                return None, "file %s does not exist" % a.file
            if not os.path.isfile(a.file):
                return None, "%s is not a file" % a.file
            try:
                with open(a.file) as f:
                    text = f.read()
            except (IOError, OSError, UnicodeDecodeError) as exc:
                return None, "cannot read %s: %s" % (a.file, exc)
            if not text.strip():
                return None, "file %s is empty" % a.file
            return text, None
        if a.param:
            if not rospy.has_param(a.param):
                return None, "parameter %s does not exist (load the description first, e.g. with " \
                             "<param name=\"robot_description\" command=\"xacro ...\"/>)" % a.param
            text = rospy.get_param(a.param)
            if not isinstance(text, str) or not text.strip():
                return None, "parameter %s is empty or not a string" % a.param
            return text, None
        if a.database:
            return DATABASE_TEMPLATE.format(a.database), None
        text = sys.stdin.read()
        if not text.strip():
            return None, "stdin was empty"
        return text, None

    def wait_service(self, name):
        timeout = self.args.timeout if self.args.timeout > 0 else None
        rospy.loginfo("Waiting for service %s" % name)
        try:
            rospy.wait_for_service(name, timeout=timeout)
        except rospy.ROSException:
            return False
        return True

    def call(self, name, srv_type, **kw):
        if not self.wait_service(name):
            return None, "service %s not available after %.1f s (is the simulator running?)" % (
                name, self.args.timeout)
        try:
            return rospy.ServiceProxy(name, srv_type)(**kw), None
        except (rospy.ServiceException, rospy.ROSException) as exc:
            return None, "service call %s failed: %s" % (name, exc)

    def run(self):
        a = self.args
        if a.wait and not self.wait_for_model(a.wait):
            return 0
        text, err = (self._xml, None) if self._xml is not None else self.load_xml()
        if err:
            return self.fail(err)
        try:
            root = ET.fromstring(text)
        except ET.ParseError as exc:
            return self.fail("invalid XML: %s" % exc)
        if a.package_to_model:
            for mesh in root.iter("mesh"):
                fn = mesh.get("filename")
                if fn and fn.startswith("package://"):
                    mesh.set("filename", "model://" + fn[len("package://"):])
            text = ET.tostring(root, encoding="unicode")
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = a.x, a.y, a.z
        q = quat_from_rpy(a.R, a.P, a.Y)
        pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q
        service = "%s/spawn_%s_model" % (self.ns, "urdf" if a.urdf else "sdf")
        resp, err = self.call(service, SpawnModel, model_name=a.model, model_xml=text,
                              robot_namespace=a.robot_namespace, initial_pose=pose,
                              reference_frame=a.reference_frame)
        if err:
            return self.fail(err)
        rospy.loginfo("Spawn status: %s" % resp.status_message)
        if not resp.success:
            return self.fail("spawn service failed: %s" % resp.status_message)
        if a.joints:
            resp, err = self.call("%s/set_model_configuration" % self.ns, SetModelConfiguration,
                                  model_name=a.model, urdf_param_name="",
                                  joint_names=[j[0] for j in a.joints],
                                  joint_positions=[j[1] for j in a.joints])
            if err:
                return self.fail(err)
            if not resp.success:
                return self.fail("set_model_configuration failed: %s" % resp.status_message)
        if a.unpause:
            rospy.loginfo("Unpausing physics")
            _, err = self.call("%s/unpause_physics" % self.ns, Empty)
            if err:
                return self.fail(err)
        if a.bond:
            rospy.on_shutdown(self.delete_model)
            rospy.loginfo("Waiting for shutdown to delete model %s" % a.model)
            rospy.spin()
        return 0

    def wait_for_model(self, name):
        found = []
        sub = rospy.Subscriber("%s/model_states" % self.ns, ModelStates,
                               lambda m: found.append(True) if name in m.name else None)
        rospy.loginfo("Waiting for model %s before proceeding." % name)
        while not rospy.is_shutdown() and not found:
            time.sleep(0.1)
        sub.unregister()
        return bool(found)

    def delete_model(self):
        rospy.loginfo("Deleting model %s" % self.args.model)
        try:
            rospy.ServiceProxy("%s/delete_model" % self.ns, DeleteModel)(model_name=self.args.model)
        except (rospy.ServiceException, rospy.ROSException) as exc:
            rospy.logerr("delete_model failed: %s" % exc)
