"""User tests of the control device (seed 000, section III-H): RC_usertest_endpoint (a goal
sphere, distance_to_endpoint, colour change under a threshold) and RC_usertest_trajectory (a
shown trajectory, distance from the end effector to its nearest point). Both log the distances
over time to CSV and plot them (PNG) like the seed's figure 17."""
import math

import rospy
from std_msgs.msg import Bool, Float64
from visualization_msgs.msg import Marker

from modrob_viz import markers
from modrob_viz.distance_log import DistanceLog
from modrob_viz.errors import VizError
from modrob_viz.geometry import PolylineDistance
from modrob_viz.ros.common import EndEffectorSampler, latched


class EndpointUserTest(object):
    """A SPHERE at ``goal`` on ``~goal_marker`` that turns ``reached_color`` while the end effector
    is closer than ``threshold`` m; ``distance_to_endpoint`` (Float64) and ``~goal_reached`` (Bool)
    at ``rate`` Hz; CSV/PNG written to ``csv_file``/``plot_file`` every ``save_period`` s and on exit."""

    def __init__(self, base_frame, ee_frame, goal, threshold=0.02, rate=20.0, diameter=0.04, color="red",
                 reached_color="green", csv_file="", plot_file="", save_period=5.0, trajectory=None,
                 traj_color="black", width=0.005):
        if len(goal) != 3 or not all(math.isfinite(v) for v in goal):
            raise VizError("~goal must be three finite numbers [x, y, z], got %r" % (goal,))
        self.base_frame = base_frame
        self.goal = tuple(goal)
        self.threshold = threshold
        self.colors = (markers.parse_color(color), markers.parse_color(reached_color))
        self.diameter = diameter
        self.csv_file, self.plot_file = csv_file, plot_file
        self.log = DistanceLog()
        self.start = None
        self.reached = None
        self.trajectory = PolylineDistance(trajectory) if trajectory is not None else None
        self.sampler = EndEffectorSampler(base_frame, ee_frame)
        self.goal_pub = latched("~goal_marker", Marker)
        self.reached_pub = latched("~goal_reached", Bool)
        self.dist_pub = rospy.Publisher("distance_to_endpoint", Float64, queue_size=10)
        if self.trajectory is not None:
            self.traj_pub = latched("~trajectory_marker", Marker)
            self.traj_pub.publish(markers.line_strip(self.trajectory.points, base_frame, traj_color, width,
                                                     ns="usertest_trajectory"))
            self.traj_dist_pub = rospy.Publisher("distance_to_trajectory", Float64, queue_size=10)
        self._show(False)
        self.timer = rospy.Timer(rospy.Duration(1.0 / rate), self.step, reset=True)
        if save_period > 0 and (csv_file or plot_file):
            self.save_timer = rospy.Timer(rospy.Duration(save_period), self.save, reset=True)
        rospy.on_shutdown(self.save)
        rospy.loginfo("%s: goal (%.3f, %.3f, %.3f) in %s, threshold %.3f m", rospy.get_name(),
                      self.goal[0], self.goal[1], self.goal[2], base_frame, threshold)

    def _show(self, reached):
        if reached == self.reached:
            return
        self.reached = reached
        self.goal_pub.publish(markers.sphere(self.goal, self.base_frame, self.diameter, self.colors[reached]))
        self.reached_pub.publish(Bool(reached))

    def step(self, _event=None):
        s = self.sampler.sample()
        if s is None:
            return
        p, stamp = s
        d = math.dist(p, self.goal)
        self.dist_pub.publish(Float64(d))
        d_traj = float("nan")
        if self.trajectory is not None:
            d_traj = self.trajectory.distance(p)
            self.traj_dist_pub.publish(Float64(d_traj))
        now = rospy.get_time()
        self.start = now if self.start is None else self.start
        self.log.add(now - self.start, d, d_traj)
        inside = d < self.threshold
        if inside and not self.reached:
            rospy.loginfo("%s: goal reached (distance %.4f m < %.4f m) after %.1f s", rospy.get_name(), d,
                          self.threshold, now - self.start)
        self._show(inside)

    def save(self, _event=None):
        if not len(self.log):
            return
        try:
            if self.csv_file:
                self.log.write_csv(self.csv_file)
            if self.plot_file:
                self.log.plot(self.plot_file, title=rospy.get_name().lstrip("/"))
        except (VizError, OSError, ValueError) as err:
            rospy.logerr("%s: could not save the distance log: %s", rospy.get_name(), err)
