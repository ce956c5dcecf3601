#!/usr/bin/env python3
"""Keys to geometry_msgs/Twist on cmd_vel (teleop_twist_keyboard's key map; help on start).
   rosrun teleop_twist_keyboard teleop_twist_keyboard.py _speed:=0.3 cmd_vel:=/robot/cmd_vel"""
import signal
import sys

import rospy

from keyboard_teleop.keys import HELP, KeyTeleop
from keyboard_teleop.node import Publisher, raw_terminal, read_key, say


def main():
    rospy.init_node("teleop_twist_keyboard", disable_signals=True)
    teleop = KeyTeleop(rospy.get_param("~speed", 0.5), rospy.get_param("~turn", 1.0),
                       rospy.get_param("~speed_limit", 1000.0), rospy.get_param("~turn_limit", 1000.0))
    key_timeout = float(rospy.get_param("~key_timeout", 0.5))
    pub = Publisher(float(rospy.get_param("~repeat_rate", 0.0)), bool(rospy.get_param("~stamped", False)),
                    str(rospy.get_param("~frame_id", "")))
    # a stop from outside (roslaunch, kill) ends the loop too: the terminal and the zero twist follow
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(0))
    try:
        pub.wait_for_subscribers(print)
        with raw_terminal(sys.stdin):
            say(HELP)
            say(teleop.status())
            pub.update(teleop.twist())
            while not rospy.is_shutdown():
                key = read_key(sys.stdin, key_timeout if key_timeout > 0 else None)
                twist, lines, done = teleop.press(key)
                for line in lines:
                    say(line)
                if twist is not None:
                    pub.update(twist)
                if done:
                    break
    finally:
        pub.stop()                 # publishes the zero twist
        rospy.signal_shutdown("teleop_twist_keyboard quit")


if __name__ == "__main__":
    main()
