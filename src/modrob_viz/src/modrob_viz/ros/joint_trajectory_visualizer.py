"""joint_trajectory_visualizer: a bag of joint points -> KDL forward kinematics for every point
-> LINE_STRIP of the end-effector path, shown before the robot moves (seed 000, III-C/D).
Beyond the seed: direction arrows and automatic milestone reduction (Douglas-Peucker)."""
import rospy
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
from visualization_msgs.msg import Marker, MarkerArray

from modrob_viz import bag_io, joint_path, markers
from modrob_viz.errors import VizError
from modrob_viz.ros.common import check_link, latched
from modrob_viz.ros.trajectory_3d import BagWatcher, report_bag_problem


def reduced_trajectory_msg(path, indices):
    msg = JointTrajectory()
    msg.joint_names = list(path.names)
    for i in indices:
        p = JointTrajectoryPoint()
        p.positions = path.positions[i].tolist()
        p.time_from_start = rospy.Duration.from_sec(float(path.times[i]))
        msg.points.append(p)
    return msg


class JointTrajectoryVisualizer(object):
    """Publishes (latched) ``~marker`` (the end-effector path, every point), ``~arrows``
    (direction), and with ``reduce_tolerance`` > 0 ``~milestones`` (SPHERE_LIST of the kept
    points) and ``~reduced_trajectory`` (the JointTrajectory of the kept points)."""

    def __init__(self, tree, bag_file, ee_link, base_frame="", color="red", width=0.005, arrow_spacing=0.08,
                 reduce_tolerance=0.0, watch=True):
        self.tree = tree
        self.bag_file = bag_file
        self.ee_link = ee_link
        self.base_frame = base_frame or tree.root
        check_link(tree, self.ee_link, "~ee_link")
        check_link(tree, self.base_frame, "~base_frame")
        self.color = markers.parse_color(color)
        self.width = width
        self.arrow_spacing = arrow_spacing
        self.reduce_tolerance = reduce_tolerance
        self.pub = latched("~marker", Marker)
        self.arrow_pub = latched("~arrows", MarkerArray)
        self.milestone_pub = latched("~milestones", Marker)
        self.reduced_pub = latched("~reduced_trajectory", JointTrajectory)
        self.ee_points = None
        self.watcher = BagWatcher(bag_file, self.load, watch)

    def load(self):
        try:
            path = bag_io.read_joint_trajectory(self.bag_file)
            ee = joint_path.end_effector_path(self.tree, path, self.ee_link, self.base_frame)
        except VizError as err:
            report_bag_problem("joint_trajectory_visualizer", err)
            return
        self.ee_points = ee
        self.pub.publish(markers.line_strip(ee, self.base_frame, self.color, self.width,
                                            ns="joint_trajectory"))
        if self.arrow_spacing > 0:
            self.arrow_pub.publish(markers.direction_arrows(ee, self.base_frame, self.arrow_spacing))
        rospy.loginfo("joint_trajectory_visualizer: %d joint points from %s -> end-effector path of %s in %s",
                      len(path), self.bag_file, self.ee_link, self.base_frame)
        if self.reduce_tolerance > 0 and len(path):
            kept = joint_path.reduce_milestones(ee, self.reduce_tolerance)
            self.milestone_pub.publish(markers.points_marker(ee[kept], self.base_frame, 3 * self.width))
            self.reduced_pub.publish(reduced_trajectory_msg(path, kept))
            rospy.loginfo("joint_trajectory_visualizer: %d of %d milestones kept (tolerance %.4f m)",
                          len(kept), len(path), self.reduce_tolerance)
