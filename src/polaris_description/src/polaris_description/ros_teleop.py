"""Keyboard teleop node (thin ROS layer). The terminal is put in raw mode and always restored;
zero is published on exit."""
import os
import select
import sys
import termios
import tty

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Float64

from polaris_description import geometry as G
from polaris_description.errors import CommandError
from polaris_description.teleop import TeleopState, help_text


class TeleopNode(object):
    def __init__(self, use_cmd_vel=False):
        self.state = TeleopState()
        self.use_cmd_vel = use_cmd_vel
        if use_cmd_vel:
            self.cmd = rospy.Publisher("cmd_vel", Twist, queue_size=1)
        else:
            self.pubs = {k: rospy.Publisher("/%s/command" % G.CONTROLLERS[k], Float64, queue_size=1)
                         for k in ("steer_left", "steer_right", "rear_left", "rear_right")}

    def publish(self):
        s = self.state
        if self.use_cmd_vel:
            v, w = s.twist()
            msg = Twist()
            msg.linear.x, msg.angular.z = v, w
            self.cmd.publish(msg)
        else:
            for k in ("rear_left", "rear_right"):
                self.pubs[k].publish(Float64(s.rate))
            for k in ("steer_left", "steer_right"):
                self.pubs[k].publish(Float64(s.steer))

    def run(self, stream=sys.stdin):
        print(help_text())
        fd = stream.fileno()
        old = termios.tcgetattr(fd) if stream.isatty() else None
        try:
            if old is not None:
                tty.setcbreak(fd, termios.TCSANOW)   # keep keys typed during start-up
            rate = rospy.Rate(20)
            while not rospy.is_shutdown():
                ready, _, _ = select.select([fd], [], [], 0.05)
                if ready:
                    key = os.read(fd, 1).decode("utf-8", "replace")
                    if key == "":
                        break
                    if key == "\x03":
                        break
                    try:
                        action = self.state.press(key)
                    except CommandError:
                        print("\rkey %r is not bound (h: see the table above)" % key)
                        continue
                    print("\r" + self.state.status(), flush=True)
                    if action == "quit":
                        break
                self.publish()
                rate.sleep()
        finally:
            self.state.rate, self.state.steer = 0.0, 0.0
            self.publish()
            if old is not None:
                termios.tcsetattr(fd, termios.TCSADRAIN, old)


def main():
    rospy.init_node("polaris_teleop")
    node = TeleopNode(bool(rospy.get_param("~use_cmd_vel", False)))
    node.run()
