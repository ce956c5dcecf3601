"""ball_mover: spawns the tracked ball (a magenta sphere, visual only: it rolls over nothing) and
moves it along a known path through /gazebo/set_model_state, in simulated time."""
import rospy
from gazebo_msgs.msg import ModelState
from gazebo_msgs.srv import SpawnModel
from geometry_msgs.msg import Point, Pose, Quaternion

from ptrz_camera.tracking.paths import FigureEight

BALL_SDF = """<?xml version="1.0"?>
<sdf version="1.6"><model name="{name}"><static>false</static><link name="link">
  <gravity>false</gravity>
  <inertial><mass>0.45</mass><inertia><ixx>0.0036</ixx><iyy>0.0036</iyy><izz>0.0036</izz></inertia></inertial>
  <visual name="visual"><geometry><sphere><radius>{r}</radius></sphere></geometry>
    <material><ambient>0.9 0 0.75 1</ambient><diffuse>0.9 0 0.75 1</diffuse></material></visual>
</link></model></sdf>"""


class BallMover(object):
    def __init__(self, name, radius, path, rate):
        self.name, self.radius, self.path, self.rate = name, radius, path, rate
        self.pub = rospy.Publisher("/gazebo/set_model_state", ModelState, queue_size=1)

    def spawn(self):
        rospy.wait_for_service("/gazebo/spawn_sdf_model", timeout=120)
        x, y = self.path.position(0.0)
        pose = Pose(Point(x, y, self.radius), Quaternion(0, 0, 0, 1))
        res = rospy.ServiceProxy("/gazebo/spawn_sdf_model", SpawnModel)(
            self.name, BALL_SDF.format(name=self.name, r=self.radius), "", pose, "world")
        if not res.success:
            raise RuntimeError("cannot spawn the ball: %s" % res.status_message)

    def run(self):
        rate = rospy.Rate(self.rate)
        t0 = rospy.get_time()
        while not rospy.is_shutdown():
            t = rospy.get_time() - t0
            (x, y), (vx, vy) = self.path.position(t), self.path.velocity(t)
            msg = ModelState(model_name=self.name, reference_frame="world")
            msg.pose.position = Point(x, y, self.radius)
            msg.pose.orientation.w = 1.0
            msg.twist.linear.x, msg.twist.linear.y = vx, vy
            self.pub.publish(msg)
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                return


def main():
    rospy.init_node("ball_mover")
    path = FigureEight(float(rospy.get_param("~cx", 3.5)), float(rospy.get_param("~cy", 0.0)),
                       float(rospy.get_param("~ax", 2.0)), float(rospy.get_param("~ay", 1.2)),
                       float(rospy.get_param("~period", 30.0)))
    mover = BallMover(rospy.get_param("~name", "ball"), float(rospy.get_param("~radius", 0.11)), path,
                      float(rospy.get_param("~rate", 100.0)))
    try:
        mover.spawn()
    except (RuntimeError, rospy.ROSException) as exc:
        rospy.logerr("ball_mover: %s" % exc)
        return 1
    mover.run()
    return 0
