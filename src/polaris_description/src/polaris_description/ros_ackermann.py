"""Ackermann node (thin ROS layer): cmd_vel -> the steering position controllers and the wheel
velocity controllers. Commands older than ~timeout s stop the wheels (steering kept)."""
import threading

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Float64

from polaris_description import geometry as G
from polaris_description.ackermann import Ackermann
from polaris_description.errors import PolarisError


class AckermannNode(object):
    def __init__(self, ackermann, rate=50.0, timeout=0.5, four_wd=False):
        self.ack = ackermann
        self.timeout = rospy.Duration(timeout)
        self.lock = threading.Lock()
        self.latest = None
        self.stamp = None
        keys = ["steer_left", "steer_right", "rear_left", "rear_right"]
        if four_wd:
            keys += ["front_left", "front_right"]
        self.pubs = {k: rospy.Publisher("/%s/command" % G.CONTROLLERS[k], Float64, queue_size=1)
                     for k in keys}
        self.sub = rospy.Subscriber("cmd_vel", Twist, self.on_cmd, queue_size=1)
        self.timer = rospy.Timer(rospy.Duration(1.0 / rate), self.tick, reset=True)

    def on_cmd(self, msg):
        with self.lock:
            self.latest = (msg.linear.x, msg.angular.z)
            self.stamp = rospy.Time.now()

    def tick(self, _event):
        with self.lock:
            cmd, stamp = self.latest, self.stamp
        if cmd is None:
            return
        v, w = cmd
        if rospy.Time.now() - stamp > self.timeout or rospy.Time.now() < stamp:
            v, w = 0.0, 0.0
        try:
            c = self.ack.command(v, w)
        except PolarisError as e:
            rospy.logwarn_throttle(5.0, "ackermann: %s; command ignored" % e)
            return
        if c.clamped:
            rospy.logwarn_throttle(5.0, "ackermann: turn radius below %.2f m is beyond the steering limit; "
                                        "clamped" % (1.0 / self.ack.k_max))
        values = {"steer_left": c.steer_left, "steer_right": c.steer_right,
                  "rear_left": c.rear_left, "rear_right": c.rear_right,
                  "front_left": None, "front_right": None}
        if "front_left" in self.pubs:
            # front wheels roll on their own circles: rate = v * (distance to the centre) / (R r)
            fl, fr = self.ack.front_wheel_rates(v, c.curvature)
            values["front_left"], values["front_right"] = fl, fr
        for k, pub in self.pubs.items():
            pub.publish(Float64(values[k]))


def main():
    rospy.init_node("polaris_ackermann")
    ack = Ackermann(same_angle=bool(rospy.get_param("~same_angle", False)))
    AckermannNode(ack, float(rospy.get_param("~rate", 50.0)), float(rospy.get_param("~timeout", 0.5)),
                  bool(rospy.get_param("~four_wd", False)))
    rospy.spin()
