"""joint_trajectory_simulator: plays a joint trajectory as modrob_msgs/RobotConfigMeasured and
sensor_msgs/JointState so the RViz model follows it, and measures how far the travelled
end-effector path (tf) diverges from the desired one (KDL) (seed 000, section III-E).
Beyond the seed: the passed part of the desired path is dimmed or clipped while playing."""
import queue
import threading

import rospy
from modrob_msgs.msg import RobotConfigMeasured
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64, Int32
from trajectory_msgs.msg import JointTrajectory
from visualization_msgs.msg import Marker, MarkerArray

from modrob_viz import bag_io, geometry, joint_path, markers
from modrob_viz.errors import VizError
from modrob_viz.joint_path import JointPath
from modrob_viz.ros.common import EndEffectorSampler, check_link, latched


class JointTrajectorySimulator(object):
    """Plays the trajectory of ``bag_file`` (or every JointTrajectory arriving on ``topic`` when
    no bag is given): the last of every ``keep_every`` points (or the Douglas-Peucker milestones
    when ``reduce_tolerance`` > 0), one every ``pause`` s, on ``/<robot_ns>/robot_config_measured``
    and (``publish_joint_states``) ``joint_states``. Publishes ``~desired`` (dimmed/clipped as it
    is passed, ``passed_style``), ``~travelled``, ``~arrows`` and, once played, the divergence
    ``~divergence_max`` / ``~divergence_rms`` [m] and ``~played_points``."""

    def __init__(self, tree, ee_link, base_frame="", robot_ns="modrob0", bag_file="",
                 topic="/tp_rv_topic", pause=0.003, keep_every=5, reduce_tolerance=0.0, passed_style="dim",
                 publish_joint_states=True, sample_rate=100.0, settle_time=1.0, loop=False, color="red",
                 width=0.005, arrow_spacing=0.08):
        self.tree = tree
        self.ee_link = ee_link
        self.base_frame = base_frame or tree.root
        check_link(tree, ee_link, "~ee_link")
        check_link(tree, self.base_frame, "~base_frame")
        markers.progress_strip([], 0, self.base_frame, color, width, passed_style)  # validates the style
        joint_path.decimate(1, keep_every)  # validates keep_every
        self.bag_file = bag_file
        self.pause = pause
        self.keep_every = keep_every
        self.reduce_tolerance = reduce_tolerance
        self.passed_style = passed_style
        self.publish_joint_states = publish_joint_states
        self.settle_time = settle_time
        self.loop = loop
        self.color = markers.parse_color(color)
        self.width = width
        self.arrow_spacing = arrow_spacing
        self.config_topic = "/%s/robot_config_measured" % robot_ns.strip("/") if robot_ns.strip("/") \
            else "/robot_config_measured"
        self.config_pub = rospy.Publisher(self.config_topic, RobotConfigMeasured, queue_size=100)
        self.js_pub = rospy.Publisher("joint_states", JointState, queue_size=100)
        self.desired_pub = latched("~desired", Marker)
        self.travelled_pub = latched("~travelled", Marker)
        self.arrow_pub = latched("~arrows", MarkerArray)
        self.max_pub = latched("~divergence_max", Float64)
        self.rms_pub = latched("~divergence_rms", Float64)
        self.played_pub = latched("~played_points", Int32)
        self.sampler = EndEffectorSampler(self.base_frame, ee_link)
        self.lock = threading.Lock()
        self.sampling_since = None
        self.travelled = []
        self.inbox = queue.Queue()
        if not bag_file:
            self.sub = rospy.Subscriber(topic, JointTrajectory, self.inbox.put, queue_size=5)
            rospy.loginfo("joint_trajectory_simulator: waiting for trajectories on %s",
                          rospy.resolve_name(topic))
        self.timer = rospy.Timer(rospy.Duration(1.0 / sample_rate), self._sample, reset=True)

    # -- tf sampling (timer thread): only samples stamped after playing started count
    def _sample(self, _event=None):
        with self.lock:
            since = self.sampling_since
        if since is None:
            return
        s = self.sampler.sample()
        if s is None or s[1] < since:
            return
        with self.lock:
            if not self.travelled or self.travelled[-1][1] != s[1]:
                self.travelled.append(s)

    def spin(self):
        while not rospy.is_shutdown():
            if self.bag_file:
                try:
                    path = bag_io.read_joint_trajectory(self.bag_file)
                except VizError as err:
                    rospy.logerr("joint_trajectory_simulator: %s", err)
                    rospy.spin()
                    return
                self.play(path)
                if not self.loop:
                    rospy.spin()
                    return
            else:
                try:
                    msg = self.inbox.get(timeout=0.2)
                except queue.Empty:
                    continue
                try:
                    path = JointPath.from_points(msg.joint_names, msg.points)
                except VizError as err:
                    rospy.logerr("joint_trajectory_simulator: trajectory refused: %s", err)
                    continue
                self.play(path)

    def play(self, path):
        try:
            ee = joint_path.end_effector_path(self.tree, path, self.ee_link, self.base_frame)
        except VizError as err:
            rospy.logerr("joint_trajectory_simulator: %s", err)
            return None
        if len(path) == 0:
            rospy.logwarn("joint_trajectory_simulator: the trajectory has no points")
            return None
        if self.reduce_tolerance > 0:
            indices = joint_path.reduce_milestones(ee, self.reduce_tolerance)
        else:
            indices = joint_path.decimate(len(path), self.keep_every)
        rospy.loginfo("joint_trajectory_simulator: playing %d of %d points (pause %.4f s) on %s",
                      len(indices), len(path), self.pause, self.config_topic)
        self._publish_desired(ee, 0)
        if self.arrow_spacing > 0:
            self.arrow_pub.publish(markers.direction_arrows(ee, self.base_frame, self.arrow_spacing))
        with self.lock:
            self.travelled = []
            self.sampling_since = None
        last_stamp, last_shown = None, rospy.get_time()
        for k, i in enumerate(indices):
            if rospy.is_shutdown():
                return None
            last_stamp = self._publish_point(path, i)
            if k == 0:
                with self.lock:
                    self.sampling_since = last_stamp
            if rospy.get_time() - last_shown > 0.1:
                self._publish_desired(ee, i + 1)
                self._publish_travelled()
                last_shown = rospy.get_time()
            rospy.sleep(self.pause)
        self._publish_desired(ee, len(ee))
        # robot_state_publisher drops joint states that come faster than its publish_frequency:
        # send the last point once more, after that interval, and wait for it in tf.
        rospy.sleep(0.05)
        last_stamp = self._publish_point(path, indices[-1])
        final = self.sampler.sample(last_stamp, timeout=self.settle_time)
        with self.lock:
            self.sampling_since = None
            travelled = [s[0] for s in self.travelled if s[1] <= last_stamp]
        if final is not None:
            travelled.append(final[0])
        self.played_pub.publish(Int32(len(indices)))
        self.travelled_pub.publish(markers.line_strip(travelled, self.base_frame, "turquoise", self.width,
                                                      ns="travelled"))
        try:
            div = geometry.divergence(ee, travelled)
        except VizError as err:
            rospy.logerr("joint_trajectory_simulator: no divergence measured: %s", err)
            return None
        self.max_pub.publish(Float64(div.max))
        self.rms_pub.publish(Float64(div.rms))
        rospy.loginfo("joint_trajectory_simulator: divergence of the travelled from the desired end-effector "
                      "path: %s", div)
        return div

    def _publish_point(self, path, i):
        stamp = rospy.Time.now()
        config = RobotConfigMeasured()
        config.header.stamp = stamp
        config.header.frame_id = self.base_frame
        config.joint_names = list(path.names)
        config.joint_angles = path.positions[i].tolist()
        self.config_pub.publish(config)
        if self.publish_joint_states:
            js = JointState()
            js.header.stamp = stamp
            js.name = list(path.names)
            js.position = config.joint_angles
            self.js_pub.publish(js)
        return stamp

    def _publish_travelled(self):
        with self.lock:
            points = [p for p, _ in self.travelled]
        self.travelled_pub.publish(markers.line_strip(points, self.base_frame, "turquoise", self.width,
                                                      ns="travelled"))

    def _publish_desired(self, ee, passed):
        self.desired_pub.publish(markers.progress_strip(ee, passed, self.base_frame, self.color, self.width,
                                                        self.passed_style, ns="desired"))
