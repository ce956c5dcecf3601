"""ekf_localization_node's ROS side: one subscriber per input (callbacks turn messages into
measurements, frames resolved through tf, and queue them), a timer at ``frequency`` of ROS time
(simulated time under use_sim_time) that feeds the queue to the filter in time order and publishes
``odometry/filtered`` (and ``accel/filtered``) and the world -> base_link transform (or, with
world_frame = map_frame, map -> odom); ``set_pose`` as a topic and a service."""
import collections
import threading

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import (AccelWithCovarianceStamped, PoseWithCovarianceStamped, TransformStamped,
                               TwistWithCovarianceStamped)
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu

from robot_localization import ekf
from robot_localization.measurements import (IDENTITY, Frame, PoseInput, cov6, imu_measurements,
                                             matrix_of_quaternion, quaternion_of_rpy, twist_measurement)
from robot_localization.srv import SetPose, SetPoseResponse

MIN_QUEUE = 100
HOLD = 0.5          # s: the longest a measurement waits for the other inputs (see EkfNode._horizon)
MESSAGE_TYPES = {"odom": Odometry, "twist": TwistWithCovarianceStamped, "imu": Imu,
                 "pose": PoseWithCovarianceStamped}


class InputHandler(object):
    """One input's callback: message -> measurements (ekf.Measurement) into the node's queue."""

    def __init__(self, node, cfg):
        self.node, self.cfg = node, cfg
        self.pose = PoseInput(cfg.config, cfg.differential, cfg.relative)
        self.last_stamp = None
        self.count = 0
        # at least MIN_QUEUE: rospy keeps only the newest queue_size messages of those it reads at
        # once, and this Python node can stall for a fraction of a second on a loaded machine (a
        # busy filter tick, the GIL, the scheduler), where C++ robot_localization's threads keep up.
        # Messages dropped that way leave a gap the filter fills with its last speed: a 0.5 s stall
        # at the start of a drive cost 5 cm of 1.6 m with 10 (a dropped stop message lets the
        # estimate run on at the last speed); with 100 (2 s at 50 Hz) nothing is lost
        self.sub = rospy.Subscriber(cfg.topic, MESSAGE_TYPES[cfg.kind], self.callback,
                                    queue_size=max(cfg.queue_size, MIN_QUEUE))

    def callback(self, msg):
        t = msg.header.stamp.to_sec()
        if self.last_stamp is not None and t < self.last_stamp:
            self.node.warn(self.cfg.name + "old", "%s: a message stamped %.3f s is older than the previous "
                           "one (%.3f s): ignored (a bad time stamp, or the clock went back)"
                           % (self.cfg.topic, t, self.last_stamp))
            return
        self.last_stamp = t
        try:
            found = getattr(self, "_" + self.cfg.kind)(msg, t)
        except (ValueError, tf2_ros.TransformException) as err:
            self.node.warn(self.cfg.name + "bad", "%s: %s: message ignored" % (self.cfg.topic, err))
            return
        self.count += 1
        self.node.enqueue(self.cfg.name, t, found)

    def _m(self, got, t, threshold):
        if got is None:
            return []
        values, cov, mask = got
        return [ekf.Measurement(values, cov, mask, t, threshold, self.cfg.topic)]

    def _pose_part(self, frame, pose_msg, t):
        if not self.pose.mask.any():
            return []
        world_from = self.node.frame_to(self.node.cfg.world_frame, frame)
        p, q = pose_msg.pose.position, pose_msg.pose.orientation
        got = self.pose.measure((p.x, p.y, p.z), matrix_of_quaternion((q.x, q.y, q.z, q.w)),
                                cov6(pose_msg.covariance, "pose covariance"), t, world_from)
        threshold = self.cfg.twist_threshold if self.cfg.differential else self.cfg.pose_threshold
        return self._m(got, t, threshold)

    def _twist_part(self, frame, twist_msg, t):
        base_from = self.node.frame_to(self.node.cfg.base_link_frame, frame)
        v, w = twist_msg.twist.linear, twist_msg.twist.angular
        got = twist_measurement(self.cfg.config, (v.x, v.y, v.z), (w.x, w.y, w.z),
                                cov6(twist_msg.covariance, "twist covariance"), base_from)
        return self._m(got, t, self.cfg.twist_threshold)

    def _odom(self, msg, t):
        return (self._pose_part(msg.header.frame_id, msg.pose, t)
                + self._twist_part(msg.child_frame_id, msg.twist, t))

    def _pose(self, msg, t):
        return self._pose_part(msg.header.frame_id, msg.pose, t)

    def _twist(self, msg, t):
        return self._twist_part(msg.header.frame_id, msg.twist, t)

    def _imu(self, msg, t):
        base_from = self.node.frame_to(self.node.cfg.base_link_frame, msg.header.frame_id)
        o, w, a = msg.orientation, msg.angular_velocity, msg.linear_acceleration
        out = []
        for values, cov, mask in imu_measurements(
                self.cfg.config, self.pose, (o.x, o.y, o.z, o.w), msg.orientation_covariance, (w.x, w.y, w.z),
                msg.angular_velocity_covariance, (a.x, a.y, a.z), msg.linear_acceleration_covariance, t,
                base_from, self.cfg.remove_gravity, self.node.cfg.gravity):
            if mask[ekf.AX:].any():
                threshold = self.cfg.accel_threshold
            elif mask[ekf.ROLL:ekf.YAW + 1].any():
                threshold = self.cfg.pose_threshold
            else:
                threshold = self.cfg.twist_threshold
            out.append(ekf.Measurement(values, cov, mask, t, threshold, self.cfg.topic))
        return out


class EkfNode(object):
    def __init__(self, cfg):
        self.cfg = cfg
        self.filter = ekf.Ekf(cfg.process_noise, cfg.initial_covariance, cfg.two_d_mode)
        self.lock = threading.Lock()
        self.queue = collections.deque()
        self.last_measurement = None
        self.last_stamp = None          # of the last estimate published
        self.last_tick = None           # this node's time at the last tick
        self.latest = {}                # input name -> stamp of its newest message
        self._warned = {}
        self.tf_buffer = tf2_ros.Buffer()
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        self.tf_broadcaster = tf2_ros.TransformBroadcaster()
        self.odom_pub = rospy.Publisher("odometry/filtered", Odometry, queue_size=10)
        self.accel_pub = (rospy.Publisher("accel/filtered", AccelWithCovarianceStamped, queue_size=10)
                          if cfg.publish_acceleration else None)
        for w in cfg.warnings:
            rospy.logwarn("%s: %s" % (rospy.get_name(), w))
        self.inputs = [InputHandler(self, i) for i in cfg.inputs]
        for i in cfg.inputs:
            rospy.loginfo("%s: %s" % (rospy.get_name(), i.describe()))
        self.set_pose_sub = rospy.Subscriber("set_pose", PoseWithCovarianceStamped, self._on_set_pose,
                                             queue_size=1)
        self.set_pose_srv = rospy.Service("set_pose", SetPose, self._on_set_pose_srv)
        # reset: time going back (reset_simulation, a new bag) restarts the timer instead of ending
        # its thread, as roscpp's timers carry on
        self.timer = rospy.Timer(rospy.Duration(1.0 / cfg.frequency), self._tick, reset=True)

    # -- callbacks ------------------------------------------------------------------------------
    def warn(self, key, text, period=10.0):
        now = rospy.get_time()
        last = self._warned.get(key)
        if last is None or now - last >= period or now < last:
            self._warned[key] = now
            rospy.logwarn("%s: %s" % (rospy.get_name(), text))

    def frame_to(self, target, source):
        """The transform target <- source (IDENTITY when they are the same or source is empty)."""
        if not source or source.lstrip("/") == target:
            return IDENTITY
        tf = self.tf_buffer.lookup_transform(target, source.lstrip("/"), rospy.Time(0), rospy.Duration(0.0))
        q, t = tf.transform.rotation, tf.transform.translation
        return Frame.from_quaternion((q.x, q.y, q.z, q.w), (t.x, t.y, t.z))

    def enqueue(self, source, t, measurements):
        with self.lock:
            self.latest[source] = t
            self.queue.extend(measurements)

    def _horizon(self):
        """The time up to which every input that speaks has reported: measurements up to it are
        fused, later ones wait, so that one topic's message arriving after another's later one
        still meets the filter in time order. An input silent for HOLD seconds holds no one up."""
        if not self.latest:
            return None
        newest = max(self.latest.values())
        return max(min(self.latest.values()), newest - HOLD)

    def _on_set_pose(self, msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        values = np.zeros(ekf.N)
        values[:3] = (p.x, p.y, p.z)
        values[3:6] = ekf.rpy_of_matrix(matrix_of_quaternion((q.x, q.y, q.z, q.w)))
        cov = np.zeros((ekf.N, ekf.N))
        cov[:6, :6] = cov6(msg.pose.covariance, "set_pose covariance")
        mask = [True] * 6 + [False] * 9
        with self.lock:
            self.queue.clear()
            self.filter.set_state(values, cov, mask, msg.header.stamp.to_sec() or rospy.get_time())
        rospy.loginfo("%s: pose set to x %.3f y %.3f z %.3f yaw %.3f"
                      % (rospy.get_name(), p.x, p.y, p.z, values[ekf.YAW]))

    def _on_set_pose_srv(self, req):
        self._on_set_pose(req.pose)
        return SetPoseResponse()

    # -- the periodic update --------------------------------------------------------------------
    def _tick(self, event):
        now = rospy.get_time()
        if self.last_tick is not None and now < self.last_tick:
            self.last_stamp = None      # the clock went back (reset_simulation, a new bag): start afresh
        self.last_tick = now
        with self.lock:
            horizon = self._horizon()
            if horizon is None:
                return
            items = sorted((m for m in self.queue if m.time <= horizon), key=lambda m: m.time)
            self.queue = collections.deque(m for m in self.queue if m.time > horizon)
            f = self.filter
            for m in items:
                if not f.process(m):
                    self.warn("reject" + m.source, "%s: a measurement beyond its rejection threshold was "
                              "rejected" % m.source)
                self.last_measurement = now
            if not f.initialized:
                return
            stale = self.last_measurement is None or now - self.last_measurement > self.cfg.sensor_timeout
            if (self.cfg.predict_to_current_time or stale) and now > f.time:
                state, cov = f.predicted(now)
                stamp = now
            else:
                state, cov, stamp = f.state.copy(), f.covariance.copy(), f.time
        if self.last_stamp is not None and stamp <= self.last_stamp:
            # nothing newer: tf2 would refuse a repeated stamp (TF_REPEATED_DATA). Simulated time
            # stood still, or this node's clock is behind the measurements' stamps (the
            # simulator's /clock reaches it after its sensors' messages), so the estimate keeps
            # the newest measurement's time from one tick to the next
            return
        self.last_stamp = stamp
        if not np.all(np.isfinite(state)):
            rospy.logerr_throttle(5.0, "%s: the filter's state is not finite: check the inputs' covariances "
                                  "and process_noise_covariance" % rospy.get_name())
            return
        try:
            self._publish(state, cov, rospy.Time.from_sec(max(stamp, 0.0)))
        except rospy.ROSException:
            if not rospy.is_shutdown():     # shutting down: the publishers closed under the tick
                raise

    def _publish(self, state, cov, stamp):
        cfg = self.cfg
        q = quaternion_of_rpy(state[ekf.ROLL], state[ekf.PITCH], state[ekf.YAW])
        msg = Odometry()
        msg.header.stamp = stamp
        msg.header.frame_id = cfg.world_frame
        msg.child_frame_id = cfg.base_link_frame
        pp = msg.pose.pose
        pp.position.x, pp.position.y, pp.position.z = state[ekf.X:ekf.Z + 1]
        pp.orientation.x, pp.orientation.y, pp.orientation.z, pp.orientation.w = q
        msg.pose.covariance = list(cov[:6, :6].ravel())
        tw = msg.twist.twist
        tw.linear.x, tw.linear.y, tw.linear.z = state[ekf.VX:ekf.VZ + 1]
        tw.angular.x, tw.angular.y, tw.angular.z = state[ekf.VROLL:ekf.VYAW + 1]
        msg.twist.covariance = list(cov[6:12, 6:12].ravel())
        self.odom_pub.publish(msg)
        if self.accel_pub is not None:
            acc = AccelWithCovarianceStamped()
            acc.header.stamp, acc.header.frame_id = stamp, cfg.base_link_frame
            acc.accel.accel.linear.x, acc.accel.accel.linear.y, acc.accel.accel.linear.z = state[ekf.AX:]
            cov_a = np.zeros((6, 6))
            cov_a[:3, :3] = cov[12:, 12:]
            acc.accel.covariance = list(cov_a.ravel())
            self.accel_pub.publish(acc)
        if cfg.publish_tf:
            self._publish_tf(state, q, stamp)

    def _publish_tf(self, state, q, stamp):
        cfg = self.cfg
        tf = TransformStamped()
        tf.header.stamp = stamp + rospy.Duration(cfg.transform_time_offset)
        if cfg.world_frame == cfg.odom_frame:
            tf.header.frame_id, tf.child_frame_id = cfg.odom_frame, cfg.base_link_frame
            tf.transform.translation.x, tf.transform.translation.y, tf.transform.translation.z = state[:3]
            rot = tf.transform.rotation
            rot.x, rot.y, rot.z, rot.w = q
        else:
            # map -> odom = (map -> base_link) (odom -> base_link)^-1
            try:
                ob = self.frame_to(cfg.odom_frame, cfg.base_link_frame)
            except tf2_ros.TransformException as err:
                self.warn("map_odom", "cannot publish %s -> %s: no %s -> %s transform yet (%s)"
                          % (cfg.map_frame, cfg.odom_frame, cfg.odom_frame, cfg.base_link_frame, err))
                return
            r_mb = ekf.rotation(*state[3:6])
            r = r_mb.dot(ob.r.T)
            t = state[:3] - r.dot(ob.t)
            tf.header.frame_id, tf.child_frame_id = cfg.map_frame, cfg.odom_frame
            tf.transform.translation.x, tf.transform.translation.y, tf.transform.translation.z = t
            roll, pitch, yaw = ekf.rpy_of_matrix(r)
            (tf.transform.rotation.x, tf.transform.rotation.y, tf.transform.rotation.z,
             tf.transform.rotation.w) = quaternion_of_rpy(roll, pitch, yaw)
        self.tf_broadcaster.sendTransform(tf)
