"""The thin ROS layer of modrob_build: read ~params, run the pure build, put the results on the
parameter server / latched topics, and (for urdf_and_gazebo.launch) start the generated launch file.

Parameters read by both nodes (private):
  ~robots_file      YAML file with robots (see robot_set_config); overrides ~orders/~bases
  ~orders, ~bases   strings, robots separated by ';'
  ~gripper (false), ~grip_force (3.0), ~safety_distance (0.0); an empty string means "not
  set" (then the robots file's value, else the default)
  ~gains ("tuned" | "computed", default tuned), ~gains_table (default: config/tuned_gains.yaml)
Both nodes set ~status: "ok: <robots>" or "refused: <reason>".
"""
import os

import rospkg
import rospy
import yaml
from std_msgs.msg import String

from modrob_build.build import build_robot_set, write_outputs
from modrob_build.errors import BuildError
from modrob_build.robot_set_config import load_robots_file, specs_from_strings
from modrob_sim.waits import stop_following_clock


def _bool(value):
    if isinstance(value, str):
        return value.strip().lower() in ("1", "true", "yes", "on")
    return bool(value)


def _param(name, options, default):
    value = rospy.get_param("~" + name, "")
    if isinstance(value, str) and not value.strip():
        return options.get(name, default)
    return value


def build_from_params(out_dir=None):
    """BuildResult from the node's private parameters (raises BuildError)."""
    robots_file = rospy.get_param("~robots_file", "")
    options = {}
    if robots_file:
        specs, options = load_robots_file(robots_file)
    else:
        specs = specs_from_strings(rospy.get_param("~orders", ""), rospy.get_param("~bases", ""))
    gripper = _bool(_param("gripper", options, False))
    try:
        grip_force = float(_param("grip_force", options, 3.0))
        safety = float(_param("safety_distance", options, 0.0))
    except (TypeError, ValueError) as e:
        raise BuildError("~grip_force and ~safety_distance must be numbers: %s" % e)
    gains = str(rospy.get_param("~gains", "") or "tuned").strip()
    table = str(rospy.get_param("~gains_table", "") or "").strip() or None
    return build_robot_set(specs, gripper=gripper, grip_force=grip_force, safety_distance=safety,
                           out_dir=out_dir, gains=gains, gains_table=table)


class RobotDescriptionPublisher(object):
    """Puts /modrob<N>/robot_description and /modrob_robots on the parameter server and/or on
    latched std_msgs/String topics of the same names."""

    def __init__(self, use_params=True, use_topics=True):
        self.use_params = use_params
        self.use_topics = use_topics
        self._pubs = []    # latched publishers must stay alive

    def publish(self, result):
        robots = result.manifest["robots"]
        for robot in robots:
            urdf = result.files[robot["urdf"]]
            topic = "%s/robot_description" % robot["namespace"]
            if self.use_params:
                rospy.set_param(topic, urdf)
            if self.use_topics:
                pub = rospy.Publisher(topic, String, queue_size=1, latch=True)
                pub.publish(String(data=urdf))
                self._pubs.append(pub)
        if self.use_params:
            rospy.set_param("/modrob_robots", robots)
        if self.use_topics:
            pub = rospy.Publisher("/modrob_robots", String, queue_size=1, latch=True)
            pub.publish(String(data=yaml.safe_dump(result.manifest, sort_keys=False)))
            self._pubs.append(pub)
        for msg in result.messages:
            rospy.logwarn("robot_description_publisher: %s", msg)
        summary = ", ".join("%s %s" % (r["name"], r["order"]) for r in robots)
        rospy.set_param("~status", "ok: " + summary)
        rospy.loginfo("robot_description_publisher: %d robot(s): %s", len(robots), summary)


def run_description_publisher():
    publisher = RobotDescriptionPublisher(_bool(rospy.get_param("~publish_params", True)),
                                          _bool(rospy.get_param("~publish_topics", True)))
    try:
        publisher.publish(build_from_params())
    except BuildError as e:
        rospy.set_param("~status", "refused: %s" % e)
        rospy.logerr("robot_description_publisher: refused: %s. Nothing was published; fix the "
                     "parameters (~orders, ~bases, ~robots_file ...) and restart the node.", e)
    rospy.spin()


def run_build_and_spawn():
    """urdf_and_gazebo.launch: build into ~out_dir, publish the descriptions, then (if ~simulate)
    start the generated modrob_spawn.launch (spawn, controllers, robot_state_publisher)."""
    out_dir = os.path.expanduser(rospy.get_param("~out_dir",
                                                 os.path.join(rospkg.get_ros_home(), "modrob_build")))
    try:
        result = build_from_params(out_dir=out_dir)
        paths = write_outputs(result, out_dir)
    except BuildError as e:
        rospy.set_param("~status", "refused: %s" % e)
        rospy.logerr("create_urdf_and_gazebo: refused: %s. Nothing was written.", e)
        rospy.signal_shutdown("refused input")
        return 2
    for msg in result.messages:
        rospy.logwarn("create_urdf_and_gazebo: %s", msg)
    rospy.loginfo("create_urdf_and_gazebo: wrote %s", ", ".join(paths))
    RobotDescriptionPublisher().publish(result)
    if not _bool(rospy.get_param("~simulate", True)):
        rospy.loginfo("create_urdf_and_gazebo: simulate is false; files are in %s", out_dir)
        rospy.spin()
        return 0
    import roslaunch
    uuid = roslaunch.rlutil.get_or_generate_uuid(None, False)
    launch = roslaunch.parent.ROSLaunchParent(uuid, [os.path.join(out_dir, "modrob_spawn.launch")])
    launch.start()
    rospy.on_shutdown(launch.shutdown)
    # from here on it only keeps the spawn launch running: /clock would cost it CPU at every
    # message, beside the simulator
    stop_following_clock()
    rospy.spin()
    return 0
