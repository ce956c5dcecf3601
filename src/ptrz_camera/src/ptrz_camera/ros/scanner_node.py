"""scanner_joint_control: the seed's back-and-forth scan (ptrz_camera.scanner) on the joints."""
import rospy
from std_msgs.msg import Float64

from ptrz_camera import scanner

JOINTS = ("roll", "pan", "tilt")


class Scanner(object):
    def __init__(self, ns, joints, step, pause, lower, upper, verbose=True):
        unknown = [j for j in joints if j not in JOINTS]
        if unknown or not joints:
            raise ValueError("~joints %r: choose among %s" % (joints, ", ".join(JOINTS)))
        self.ns = ns.rstrip("/")
        self.joints = list(joints)
        self.pause = pause
        self.verbose = verbose
        self.axes = {j: scanner.ScanAxis(step, lower, upper) for j in self.joints}
        self.pubs = {j: rospy.Publisher("%s/%s_position_controller/command" % (self.ns, j), Float64,
                                        queue_size=10) for j in self.joints}

    def run(self):
        if self.verbose:
            print(" ".join("%s %.2f" % (j, self.axes[j].position) for j in self.joints))
        while not rospy.is_shutdown():
            for j in self.joints:       # as the seed: one step of each joint, a pause after each
                value = self.axes[j].advance()
                if self.verbose:
                    print("%s %.2f" % (j, value))
                try:
                    rospy.sleep(self.pause)     # simulated time when /use_sim_time is set
                except rospy.ROSInterruptException:
                    return
            for j in self.joints:
                self.pubs[j].publish(Float64(self.axes[j].position))


def main():
    rospy.init_node("ptrz_scanner")
    joints = rospy.get_param("~joints", list(JOINTS))
    if isinstance(joints, str):
        joints = joints.replace(",", " ").split()
    try:
        node = Scanner(rospy.get_param("~ns", "/ptrz"), joints,
                       float(rospy.get_param("~step", scanner.STEP)),
                       float(rospy.get_param("~pause", scanner.PAUSE)),
                       float(rospy.get_param("~lower", scanner.LOWER)),
                       float(rospy.get_param("~upper", scanner.UPPER)),
                       bool(rospy.get_param("~verbose", True)))
    except ValueError as exc:
        rospy.logerr("scanner_joint_control: %s" % exc)
        return 2
    node.run()
    return 0
