"""ROS layer of ``ee_view_broadcaster``: seed 000's end-effector-centred camera frames
(section III-G, :mod:`modrob_viz.render.ee_views`) broadcast in tf relative to the base frame."""
import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped

from modrob_viz.errors import ConfigError
from modrob_viz.render import ee_views


class EeViewBroadcaster(object):
    def __init__(self, base_frame, ee_frame, distance, views, rate, prefix="camera_ee_"):
        for v in views:
            if v not in ee_views.VIEWS:
                raise ConfigError("~views: unknown view %r (use %s)" % (v, ", ".join(ee_views.VIEWS)))
        self.base_frame, self.ee_frame, self.distance = base_frame, ee_frame, distance
        self.views, self.prefix = list(views), prefix
        self.buffer = tf2_ros.Buffer(cache_time=rospy.Duration(5.0))
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.broadcaster = tf2_ros.TransformBroadcaster()
        self._warned = False
        self._last_stamp = None
        self.timer = rospy.Timer(rospy.Duration(1.0 / rate), self._tick, reset=True)

    def frames(self):
        return [self.prefix + v for v in self.views]

    def _tick(self, _event):
        try:
            t = self.buffer.lookup_transform(self.base_frame, self.ee_frame, rospy.Time(0))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException) as err:
            if not self._warned:
                rospy.logwarn("ee_view_broadcaster: no transform %s -> %s yet (%s); waiting",
                              self.base_frame, self.ee_frame, err)
                self._warned = True
            return
        self._warned = False
        if t.header.stamp == self._last_stamp:
            return              # nothing new (tf refuses repeated stamps)
        self._last_stamp = t.header.stamp
        p = t.transform.translation
        out = []
        for v in self.views:
            pos, rpy = ee_views.view(v, (p.x, p.y, p.z), self.distance)
            msg = TransformStamped()
            msg.header.stamp = t.header.stamp
            msg.header.frame_id = self.base_frame
            msg.child_frame_id = self.prefix + v
            (msg.transform.translation.x, msg.transform.translation.y, msg.transform.translation.z) = pos
            q = ee_views.quaternion(rpy)
            (msg.transform.rotation.x, msg.transform.rotation.y, msg.transform.rotation.z,
             msg.transform.rotation.w) = q
            out.append(msg)
        self.broadcaster.sendTransform(out)
