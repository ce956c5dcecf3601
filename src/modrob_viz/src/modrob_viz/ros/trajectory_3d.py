"""trajectory_3Dpoints_recorder and trajectory_3Dpoints_visualizer (seed 000, section III-B):
end-effector positions from tf2 to a bag, and a bag of points back to a LINE_STRIP."""
import math
import os
import threading

import rospy
from std_msgs.msg import Int32
from visualization_msgs.msg import Marker, MarkerArray

from modrob_viz import bag_io, markers
from modrob_viz.errors import VizError
from modrob_viz.ros.common import EndEffectorSampler, latched


class Trajectory3DRecorder(object):
    """Samples the end effector at ``rate`` Hz and appends the points to ``bag_file`` every
    ``flush_period`` s (so the bag stays valid even if the node is killed); publishes the number
    of recorded points on ``~recorded_points``. Nothing is visualised."""

    def __init__(self, base_frame, ee_frame, bag_file, rate=20.0, bag_topic=bag_io.POINTS_TOPIC,
                 min_distance=0.0, flush_period=1.0):
        self.base_frame = base_frame
        self.bag_file = bag_file
        self.bag_topic = bag_topic
        self.min_distance = min_distance
        self.lock = threading.Lock()
        self.pending = []
        self.last = None
        self.count = 0
        bag_io.write_points(bag_file, [], base_frame, bag_topic)  # starts a fresh, valid bag now
        self.sampler = EndEffectorSampler(base_frame, ee_frame)
        self.count_pub = latched("~recorded_points", Int32)
        self.count_pub.publish(Int32(0))
        self.timer = rospy.Timer(rospy.Duration(1.0 / rate), self.sample, reset=True)
        self.flush_timer = rospy.Timer(rospy.Duration(flush_period), self.flush, reset=True)
        rospy.on_shutdown(self.flush)
        rospy.loginfo("trajectory_3Dpoints_recorder: %s in %s at %.1f Hz -> %s (topic %s)",
                      ee_frame, base_frame, rate, bag_file, bag_topic)

    def sample(self, _event=None):
        s = self.sampler.sample()
        if s is None:
            return
        p, stamp = s
        with self.lock:
            if self.last is not None and (stamp == self.last[1]
                                          or math.dist(p, self.last[0]) < self.min_distance):
                return
            self.last = (p, stamp)
            self.pending.append((p, stamp))

    def flush(self, _event=None):
        with self.lock:
            batch, self.pending = self.pending, []
            if not batch:
                return
            try:
                bag_io.write_points(self.bag_file, [b[0] for b in batch], self.base_frame, self.bag_topic,
                                    stamps=[b[1] for b in batch], mode="a")
            except VizError as err:
                rospy.logerr("trajectory_3Dpoints_recorder: %s; %d points lost", err, len(batch))
                return
            self.count += len(batch)
        self.count_pub.publish(Int32(self.count))
        rospy.loginfo_throttle(10.0, "trajectory_3Dpoints_recorder: %d points in %s" % (self.count,
                                                                                        self.bag_file))


def report_bag_problem(node, err):
    """A bag that is not there yet or still empty is worth a note; anything else is an error."""
    if getattr(err, "waiting", False):
        rospy.loginfo("%s: waiting for data: %s", node, err)
    else:
        rospy.logerr("%s: %s", node, err)


class BagWatcher(object):
    """Calls ``load()`` now and again whenever the file's modification time changes."""

    def __init__(self, path, load, watch=True, period=1.0):
        self.path = path
        self.load = load
        self.stamp = None
        self.check()
        if watch:
            self.timer = rospy.Timer(rospy.Duration(period), self.check, reset=True)

    def check(self, _event=None):
        try:
            stamp = os.stat(self.path).st_mtime_ns, os.stat(self.path).st_size
        except OSError:
            stamp = "missing"
        if stamp == self.stamp:
            return
        self.stamp = stamp
        self.load()


class Trajectory3DVisualizer(object):
    """Publishes the points of ``bag_file`` as a latched LINE_STRIP on ``~marker`` and direction
    arrows on ``~arrows``; with ``watch`` the bag is re-read when it changes. A bad bag is
    reported and the node keeps waiting for a good one."""

    def __init__(self, bag_file, bag_topic=bag_io.POINTS_TOPIC, frame_id="", color="blue", width=0.005,
                 arrow_spacing=0.08, watch=True):
        self.bag_file = bag_file
        self.bag_topic = bag_topic
        self.frame_id = frame_id
        self.color = markers.parse_color(color)
        self.width = width
        self.arrow_spacing = arrow_spacing
        self.pub = latched("~marker", Marker)
        self.arrow_pub = latched("~arrows", MarkerArray)
        self.points = []
        self.watcher = BagWatcher(bag_file, self.load, watch)

    def load(self):
        try:
            points, frame = bag_io.read_points(self.bag_file, self.bag_topic)
        except VizError as err:
            report_bag_problem("trajectory_3Dpoints_visualizer", err)
            return
        frame = self.frame_id or frame or "world"
        self.points = points
        self.pub.publish(markers.line_strip(points, frame, self.color, self.width, ns="trajectory_3d"))
        if self.arrow_spacing > 0:
            self.arrow_pub.publish(markers.direction_arrows(points, frame, self.arrow_spacing))
        rospy.loginfo("trajectory_3Dpoints_visualizer: %d points from %s shown in frame %s",
                      len(points), self.bag_file, frame)
