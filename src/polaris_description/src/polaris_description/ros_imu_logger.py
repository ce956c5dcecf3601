"""IMU logger node: /imu (sensor_msgs/Imu) -> CSV file (~file), flushed every ~flush_every rows."""
import os

import rospy
from sensor_msgs.msg import Imu

from polaris_description.imu_log import ImuCsvWriter


class ImuLogger(object):
    def __init__(self, path, flush_every=100):
        d = os.path.dirname(os.path.abspath(path))
        os.makedirs(d, exist_ok=True)
        self.stream = open(path, "w", newline="")
        self.writer = ImuCsvWriter(self.stream)
        self.flush_every = max(1, int(flush_every))
        self.sub = rospy.Subscriber("imu", Imu, self.on_imu, queue_size=100)
        rospy.on_shutdown(self.close)
        rospy.loginfo("imu_logger: writing %s" % path)

    def on_imu(self, m):
        o, w, a = m.orientation, m.angular_velocity, m.linear_acceleration
        self.writer.row(m.header.stamp.to_sec(), m.header.frame_id, (o.x, o.y, o.z, o.w), (w.x, w.y, w.z),
                        (a.x, a.y, a.z))
        if self.writer.rows % self.flush_every == 0:
            self.stream.flush()

    def close(self):
        if not self.stream.closed:
            self.stream.close()


def main():
    rospy.init_node("imu_logger")
    path = rospy.get_param("~file", "")
    if not path:
        rospy.logerr("imu_logger: set ~file to the CSV path, e.g. _file:=/tmp/imu.csv")
        raise SystemExit(2)
    ImuLogger(os.path.expanduser(path), int(rospy.get_param("~flush_every", 100)))
    rospy.spin()
