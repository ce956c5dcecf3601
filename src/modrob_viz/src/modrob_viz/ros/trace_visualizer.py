"""trace_visualizer: the end-effector trace from tf2 as a LINE_STRIP (seed 000, section III-A)."""
import collections
import math

import rospy
from visualization_msgs.msg import Marker

from modrob_viz import markers
from modrob_viz.ros.common import EndEffectorSampler, latched


class TraceVisualizer(object):
    """Samples ``ee_frame`` in ``base_frame`` at ``rate`` Hz and publishes the last ``max_points``
    positions (skipping moves shorter than ``min_distance`` m) on ``~marker``."""

    def __init__(self, base_frame, ee_frame, rate=20.0, color="red", width=0.005, max_points=5000,
                 min_distance=0.0005):
        self.base_frame = base_frame
        self.color = markers.parse_color(color)
        self.width = width
        self.min_distance = min_distance
        self.points = collections.deque(maxlen=max_points)
        self.sampler = EndEffectorSampler(base_frame, ee_frame)
        self.pub = latched("~marker", Marker)
        self.timer = rospy.Timer(rospy.Duration(1.0 / rate), self.step, reset=True)
        rospy.loginfo("trace_visualizer: tracing %s in %s at %.1f Hz on %s (at most %d points)",
                      ee_frame, base_frame, rate, rospy.resolve_name("~marker"), max_points)

    def step(self, _event=None):
        sample = self.sampler.sample()
        if sample is None:
            return
        p = sample[0]
        if self.points and math.dist(p, self.points[-1]) < self.min_distance:
            return
        self.points.append(p)
        self.pub.publish(markers.line_strip(list(self.points), self.base_frame, self.color, self.width,
                                            ns="trace"))
