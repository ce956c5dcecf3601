"""``object_detector`` node: objects from ``/scan`` (seed 4.4 A, katana_sim.detection) published
as ``geometry_msgs/PoseArray`` and cylinder markers in the scan's frame.

Subscribes ``scan`` (sensor_msgs/LaserScan). Publishes ``/katana/detected_objects`` (PoseArray),
``/katana/detection_markers`` (MarkerArray). Parameters (~): object_radius (0.033 m; <= 0:
estimate per object), object_height (0.122 m, the markers), min_beams (2), max_jump (0.05 m;
<= 0: the seed's rule only), method (centre | seed).
"""
import threading

import rospy
from geometry_msgs.msg import Pose, PoseArray
from sensor_msgs.msg import LaserScan
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from katana_sim.detection import detect
from katana_sim.errors import DetectionError


class ObjectDetectorNode(object):
    def __init__(self):
        radius = float(rospy.get_param("~object_radius", 0.033))
        self.radius = radius if radius > 0 else None
        self.height = float(rospy.get_param("~object_height", 0.122))
        self.min_beams = int(rospy.get_param("~min_beams", 2))
        jump = float(rospy.get_param("~max_jump", 0.05))
        self.max_jump = jump if jump > 0 else None
        self.method = rospy.get_param("~method", "centre")
        self.lock = threading.Lock()
        self.last = None
        self.pose_pub = rospy.Publisher("/katana/detected_objects", PoseArray, queue_size=1, latch=True)
        self.marker_pub = rospy.Publisher("/katana/detection_markers", MarkerArray, queue_size=1, latch=True)
        self._warned = False
        rospy.Subscriber("scan", LaserScan, self.on_scan, queue_size=1)

    def on_scan(self, scan):
        try:
            found = detect(scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max,
                           radius=self.radius, min_beams=self.min_beams, max_jump=self.max_jump,
                           method=self.method)
        except DetectionError as exc:
            if not self._warned:
                rospy.logwarn("object_detector: scan from %s ignored: %s" % (scan.header.frame_id, exc))
                self._warned = True
            return
        poses = PoseArray(header=scan.header)
        markers = MarkerArray(markers=[Marker(action=Marker.DELETEALL)])
        for i, d in enumerate(found):
            p = Pose()
            p.position.x, p.position.y, p.position.z = d.x, d.y, d.z
            p.orientation.w = 1.0
            poses.poses.append(p)
            m = Marker(header=scan.header, ns="detected_objects", id=i, type=Marker.CYLINDER,
                       action=Marker.ADD)
            m.pose = p
            m.scale.x = m.scale.y = 2 * d.radius
            m.scale.z = self.height
            m.color = ColorRGBA(0.1, 0.9, 0.1, 0.5)
            markers.markers.append(m)
        with self.lock:
            self.last = found
        self.pose_pub.publish(poses)
        self.marker_pub.publish(markers)


def main():
    rospy.init_node("object_detector")
    ObjectDetectorNode()
    rospy.spin()
