"""scripted_user: a stand-in for a person at the control device. It drives the robot's end
effector along the user test's trajectory (IK, with a small wobble) by publishing joint_states,
so RC_usertest_trajectory can be demonstrated and tested without a person."""
import rospy
from sensor_msgs.msg import JointState

from modrob_viz import samples


class ScriptedUser(object):
    def __init__(self, chain, points, duration=15.0, wobble=0.01, rate=30.0):
        self.chain = chain
        self.configs = samples.follow_path_ik(chain, points, wobble)
        self.period = duration / max(1, len(self.configs))
        self.rate = rate
        self.pub = rospy.Publisher("joint_states", JointState, queue_size=10)
        rospy.loginfo("scripted_user: following %d of %d path points in %.1f s",
                      len(self.configs), len(points), duration)

    def _publish(self, q):
        msg = JointState(name=list(self.chain.joint_names), position=list(q))
        msg.header.stamp = rospy.Time.now()
        self.pub.publish(msg)

    def spin(self):
        rospy.sleep(1.0)
        for q in self.configs:
            if rospy.is_shutdown():
                return
            self._publish(q)
            rospy.sleep(self.period)
        rate = rospy.Rate(self.rate)  # stay at the goal, keep the model alive
        while not rospy.is_shutdown() and self.configs:
            self._publish(self.configs[-1])
            rate.sleep()
