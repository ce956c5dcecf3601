"""dummy_trajectory_publisher: sample work-space paths (circle, line, helix, figure eight) as
geometry_msgs/PointStamped messages and/or straight to a bag (seed 000, figure 12)."""
import rospy
from geometry_msgs.msg import PointStamped
from visualization_msgs.msg import Marker

from modrob_viz import bag_io, markers, paths
from modrob_viz.ros.common import latched


class DummyTrajectoryPublisher(object):
    """Generates ``shape`` with ``shape_params``; writes it to ``bag_file`` when given, shows it
    as a latched LINE_STRIP on ``~marker`` and publishes the points one by one on ``~points``
    at ``rate`` Hz (``loop`` repeats; ``rate`` 0 publishes nothing point by point)."""

    def __init__(self, shape, shape_params, frame_id="world", bag_file="", rate=50.0, loop=False,
                 color="green", width=0.005):
        self.points = paths.generate(shape, **shape_params)
        self.frame_id = frame_id
        self.rate = rate
        self.loop = loop
        if bag_file:
            n = bag_io.write_points(bag_file, self.points, frame_id)
            rospy.loginfo("dummy_trajectory_publisher: wrote %d points of a %s to %s", n, shape, bag_file)
        self.pub = rospy.Publisher("~points", PointStamped, queue_size=100)
        self.marker_pub = latched("~marker", Marker)
        self.marker_pub.publish(markers.line_strip(self.points, frame_id, color, width, ns="dummy_" + shape))

    def spin(self):
        if self.rate <= 0:
            rospy.spin()
            return
        rate = rospy.Rate(self.rate)
        while not rospy.is_shutdown():
            for i, p in enumerate(self.points):
                msg = PointStamped()
                msg.header.seq = i
                msg.header.stamp = rospy.Time.now()
                msg.header.frame_id = self.frame_id
                msg.point.x, msg.point.y, msg.point.z = p
                self.pub.publish(msg)
                rate.sleep()
            if not self.loop:
                break
        rospy.spin()
