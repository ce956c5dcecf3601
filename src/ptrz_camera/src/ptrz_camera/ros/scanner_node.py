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
        due = None
        while not rospy.is_shutdown():
            for j in self.joints:       # as the seed: one step of each joint, a pause after each
                value = self.axes[j].advance()
                if self.verbose:
                    print("%s %.2f" % (j, value))
                # pauses end at whole multiples of the pause after the first (simulated time when
                # /use_sim_time is set), as rospy.Rate: the time this node takes to wake up and
                # publish does not add up, however fast the simulation runs against the wall clock
                # (more than two pauses behind, or the time went back: start again from now)
                now = rospy.get_time()
                if due is None or now - due > 2 * self.pause or now < due - self.pause:
                    due = now + self.pause
                else:
                    due += self.pause
                try:
                    if due > now:
                        rospy.sleep(due - now)
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
