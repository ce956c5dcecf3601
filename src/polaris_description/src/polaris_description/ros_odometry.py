"""/odom (nav_msgs/Odometry) and the odom -> base tf from /gazebo/model_states (thin ROS layer).

The node usually starts before the model is spawned: it says it waits (info) and warns only when
the model is still missing after ``MISSING_WARN`` s of simulated time (a wrong ~model_name)."""
import rospy
import tf2_ros
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import TransformStamped
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry, Path

from polaris_description.errors import PolarisError
from polaris_description.odometry import find_model, odom_from_model_state

#: s of simulated time without the model in /gazebo/model_states before that is a warning
MISSING_WARN = 10.0


class OdometryNode(object):
    def __init__(self, model_name="polaris", odom_frame="odom", base_frame="base_link_polaris", rate=50.0,
                 publish_tf=True, path_spacing=0.1, path_length=5000):
        self.model_name = model_name
        self.odom_frame = odom_frame
        self.base_frame = base_frame
        self.period = rospy.Duration(1.0 / rate) if rate > 0 else rospy.Duration(0)
        self.publish_tf = publish_tf
        self.last = None
        self.missing_since = None      # simulated time the model was first missing, None while found
        self.warned_missing = False
        self.pub = rospy.Publisher("odom", Odometry, queue_size=10)
        self.path = Path()
        self.path.header.frame_id = odom_frame
        self.path_spacing = path_spacing
        self.path_length = path_length
        self.path_pub = rospy.Publisher("odom_path", Path, queue_size=1, latch=True)
        self.tf = tf2_ros.TransformBroadcaster() if publish_tf else None
        self.sub = rospy.Subscriber("/gazebo/model_states", ModelStates, self.on_states, queue_size=1)

    def on_states(self, msg):
        now = rospy.Time.now()
        if self.last is not None and now - self.last < self.period and now >= self.last:
            return
        i = find_model(msg.name, self.model_name)
        if i is None:
            if self.missing_since is None:
                self.missing_since = now
                rospy.loginfo("odometry: waiting for model '%s' in /gazebo/model_states" % self.model_name)
            elif not self.warned_missing and (now - self.missing_since).to_sec() > MISSING_WARN:
                rospy.logwarn("odometry: model '%s' is still not in /gazebo/model_states after %.0f s "
                              "(models: %s); waiting (set ~model_name)"
                              % (self.model_name, MISSING_WARN, ", ".join(msg.name)))
                self.warned_missing = True
            return
        if self.missing_since is not None:
            rospy.loginfo("odometry: model '%s' found" % self.model_name)
        self.missing_since, self.warned_missing = None, False
        p, t = msg.pose[i], msg.twist[i]
        try:
            s = odom_from_model_state((p.position.x, p.position.y, p.position.z),
                                      (p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w),
                                      (t.linear.x, t.linear.y, t.linear.z),
                                      (t.angular.x, t.angular.y, t.angular.z))
        except PolarisError as e:
            rospy.logwarn_throttle(5.0, "odometry: %s" % e)
            return
        self.last = now
        o = Odometry()
        o.header.stamp = now
        o.header.frame_id = self.odom_frame
        o.child_frame_id = self.base_frame
        o.pose.pose = p
        o.twist.twist.linear.x, o.twist.twist.linear.y, o.twist.twist.linear.z = s.linear
        o.twist.twist.angular.x, o.twist.twist.angular.y, o.twist.twist.angular.z = s.angular
        self.pub.publish(o)
        if self.tf is not None:
            tr = TransformStamped()
            tr.header = o.header
            tr.child_frame_id = self.base_frame
            tr.transform.translation.x = p.position.x
            tr.transform.translation.y = p.position.y
            tr.transform.translation.z = p.position.z
            tr.transform.rotation = p.orientation
            self.tf.sendTransform(tr)
        self._extend_path(o)

    def _extend_path(self, o):
        """The driven path for RViz: a pose every ~path_spacing m (the newest path_length kept)."""
        p = o.pose.pose.position
        if self.path.poses:
            q = self.path.poses[-1].pose.position
            if (p.x - q.x) ** 2 + (p.y - q.y) ** 2 + (p.z - q.z) ** 2 < self.path_spacing ** 2:
                return
        ps = PoseStamped()
        ps.header = o.header
        ps.pose = o.pose.pose
        self.path.poses.append(ps)
        del self.path.poses[:-self.path_length]
        self.path.header.stamp = o.header.stamp
        self.path_pub.publish(self.path)


def main():
    rospy.init_node("polaris_odometry")
    OdometryNode(rospy.get_param("~model_name", "polaris"), rospy.get_param("~odom_frame", "odom"),
                 rospy.get_param("~base_frame", "base_link_polaris"), float(rospy.get_param("~rate", 50.0)),
                 bool(rospy.get_param("~publish_tf", True)), float(rospy.get_param("~path_spacing", 0.1)))
    rospy.spin()
