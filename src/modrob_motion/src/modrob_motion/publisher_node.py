"""ROS layer of ``motion_publisher``: one sensor_msgs/JointState in, one std_msgs/Float64 per joint out.

Topics (relative to the robot namespace ``~robot_namespace``, default the node's namespace):
    in   motion_command                       sensor_msgs/JointState (names + positions; names may be
                                              empty when every controlled joint is given in order)
    out  <controller>/command                 std_msgs/Float64, one per position controller
Parameters:
    ~robot_namespace   e.g. /modrob0 (default: the node's namespace)
    ~input_topic       default motion_command
    ~wait_timeout      wall-clock seconds to wait for the controller parameters at start (default 30)
The joint -> controller map comes from the controller parameters in the robot namespace
(``type: effort_controllers/JointPositionController``, ``joint: ...``); joint limits from
``<ns>/robot_description`` when present. Controllers whose parameters appear later (roslaunch sets a
controller YAML one parameter at a time, and a robot built at run time loads its YAML after this
node started) are picked up within a second of wall time, and at once by a command naming their
joint. A bad message is logged (what and why) and dropped.
"""
import threading
import time

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64

from modrob_msgs.errors import ModrobError
from modrob_motion.controller_map import command_topic, natural_key, position_controllers
from modrob_motion.joint_matching import JointCommandMatcher
from modrob_motion.robot_info import chain_order, parse_urdf_joints


REFRESH_PERIOD = 1.0   # s of wall time between re-reads of the controller parameters


class MotionPublisher(object):

    def __init__(self, namespace, input_topic="motion_command", wait_timeout=30.0):
        self.namespace = "/" + namespace.strip("/") if namespace.strip("/") else ""
        self._lock = threading.Lock()
        self.matcher = None
        self.publishers = {}
        self._names = frozenset()
        self._last_refresh = 0.0
        self._wait_for_controllers(wait_timeout)
        topic = input_topic if input_topic.startswith("/") else "%s/%s" % (self.namespace, input_topic)
        self.sub = rospy.Subscriber(topic, JointState, self._on_command, queue_size=10)
        rospy.loginfo("motion_publisher: %s -> %d joint controllers under %s",
                      topic, len(self.publishers), self.namespace or "/")
        self._watcher = threading.Thread(target=self._watch, name="controller_watch", daemon=True)
        self._watcher.start()

    def _wait_for_controllers(self, timeout):
        # wall-clock time: with use_sim_time at real_time_factor 0 the simulation runs on while the
        # robots are still being built and their controller YAML loaded, so 30 s of simulated time
        # passed within a few wall seconds on a loaded machine (and rospy.sleep waits forever
        # while paused)
        deadline = time.time() + timeout
        last_error = None
        while not rospy.is_shutdown():
            try:
                self._configure()
                return
            except (ModrobError, KeyError) as exc:
                last_error = exc
            if time.time() > deadline:
                break
            time.sleep(0.2)
        raise ModrobError("motion_publisher for %s: %s" % (self.namespace or "/", last_error))

    def _param_names(self):
        prefix = self.namespace + "/"
        return frozenset(n for n in rospy.get_param_names() if n.startswith(prefix))

    def _watch(self):
        """Re-read the controllers whenever the set of parameter names in the namespace changes
        (checked once a second of wall time: the simulation may be paused or far ahead)."""
        while not rospy.is_shutdown():
            time.sleep(REFRESH_PERIOD)
            try:
                changed = self._param_names() != self._names
            except (OSError, rospy.ROSException) as exc:
                rospy.logwarn_throttle(30.0, "motion_publisher: cannot list the parameters: %s" % exc)
                continue
            if changed:
                self._reread("the parameters under %s changed" % (self.namespace or "/"))

    def _configure(self):
        self._names = self._param_names()
        params = rospy.get_param(self.namespace or "/", {})
        controllers = position_controllers(params, self.namespace or "/")
        limits, order = {}, sorted(controllers, key=natural_key)
        urdf = params.get("robot_description") if isinstance(params, dict) else None
        if isinstance(urdf, str) and urdf.strip():
            try:
                joints = chain_order(parse_urdf_joints(urdf))
                limits = {j.name: j.limits for j in joints}
                chain = [j.name for j in joints if j.name in controllers]
                order = chain + [j for j in order if j not in chain]
            except ModrobError as exc:
                rospy.logwarn("motion_publisher: %s/robot_description unusable (%s); "
                              "joint limits not checked", self.namespace, exc)
        self.matcher = JointCommandMatcher(order, limits, robot=self.namespace.strip("/") or "robot")
        self.publishers = {j: rospy.Publisher(command_topic(self.namespace, controllers[j]), Float64,
                                              queue_size=10) for j in order}

    def _refresh(self, names):
        """Re-read the controller parameters when a command names a joint we do not know (at most
        once a second). roslaunch sets a controller YAML one parameter at a time, so a start-up read
        can catch a partial set (seen: 1 of 4 controllers). True if the joint set changed."""
        unknown = [n for n in names if n not in self.publishers]
        now = time.time()
        if not unknown or now - self._last_refresh < REFRESH_PERIOD:
            return False
        self._last_refresh = now
        return self._reread("a command names %s" % ", ".join(unknown))

    def _reread(self, why):
        """Read the controller parameters again; True if the joint set changed."""
        before = set(self.publishers)
        try:
            with self._lock:
                self._configure()
        except (ModrobError, KeyError) as exc:
            rospy.logwarn("motion_publisher: re-reading the controllers under %s (%s) failed: %s",
                          self.namespace or "/", why, exc)
            return False
        if set(self.publishers) == before:
            return False
        rospy.loginfo("motion_publisher: controllers under %s re-read (%s): %d joint controllers (%s)",
                      self.namespace or "/", why, len(self.publishers), ", ".join(self.publishers))
        return True

    def _on_command(self, msg):
        try:
            values = self.matcher.match(msg.name, msg.position)
        except ModrobError as exc:
            values = None
            if self._refresh(msg.name):
                try:
                    values = self.matcher.match(msg.name, msg.position)
                except ModrobError as again:
                    exc = again
            if values is None:
                rospy.logwarn("motion_publisher: command dropped: %s", exc)
                return
        with self._lock:
            for joint, value in values.items():
                self.publishers[joint].publish(Float64(value))


def main():
    rospy.init_node("motion_publisher")
    ns = rospy.get_param("~robot_namespace", rospy.get_namespace())
    try:
        MotionPublisher(ns, rospy.get_param("~input_topic", "motion_command"),
                        float(rospy.get_param("~wait_timeout", 30.0)))
    except ModrobError as exc:
        rospy.logfatal("%s", exc)
        raise SystemExit(1)
    rospy.spin()
