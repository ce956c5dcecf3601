"""ptrz_zoom: the camera's live zoom. ``<ns>/zoom`` (std_msgs/Float64, horizontal field of view in
rad) is checked against the camera model's physical range and forwarded to the camera sensor
(``<ns>/camera1/set_hfov``, whose CameraInfo follows); a value outside the range is refused with
a warning naming the range, and the camera keeps its field of view. The accepted field of view is
latched on ``<ns>/zoom_fov``."""
import threading

import rospy
from std_msgs.msg import Float64

from ptrz_camera import zoom
from ptrz_camera.errors import ZoomRangeError


class ZoomNode(object):
    def __init__(self, ns, camera, fov, fov_min, fov_max):
        self.ns = ns.rstrip("/")
        self.range = (fov_min, fov_max)
        self.lock = threading.Lock()
        self.fov_pub = rospy.Publisher(self.ns + "/zoom_fov", Float64, queue_size=1, latch=True)
        self.set_pub = rospy.Publisher(camera.rstrip("/") + "/set_hfov", Float64, queue_size=1, latch=True)
        self.fov = zoom.check_fov(fov, *self.range)
        self.fov_pub.publish(Float64(self.fov))
        self.sub = rospy.Subscriber(self.ns + "/zoom", Float64, self.on_zoom, queue_size=10)

    def on_zoom(self, msg):
        try:
            fov = zoom.check_fov(msg.data, *self.range)
        except ZoomRangeError as exc:
            rospy.logwarn("%s/zoom: %s; keeping %.4f rad" % (self.ns, exc, self.fov))
            return
        with self.lock:
            self.fov = fov
        self.set_pub.publish(Float64(fov))
        self.fov_pub.publish(Float64(fov))
        rospy.loginfo("%s/zoom: field of view %.4f rad (zoom %.2fx)" % (self.ns, fov, zoom.zoom_factor(fov)))


def main():
    rospy.init_node("ptrz_zoom")
    ns = rospy.get_param("~ns", rospy.get_namespace())
    camera = rospy.get_param("~camera", ns.rstrip("/") + "/camera1")
    try:
        ZoomNode(ns, camera, float(rospy.get_param("~fov", zoom.NOMINAL_FOV)),
                 float(rospy.get_param("~fov_min", zoom.TELE_FOV)),
                 float(rospy.get_param("~fov_max", zoom.WIDE_FOV)))
    except (ZoomRangeError, ValueError) as exc:
        rospy.logerr("ptrz_zoom: %s" % exc)
        return 2
    rospy.spin()
    return 0
