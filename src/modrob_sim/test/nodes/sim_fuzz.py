#!/usr/bin/env python3
"""rostest node: hostile requests against /gazebo (seeded; MODROB_FUZZ_SCALE scales the random
part). Each reproduced request of issue 12 first, then random ones. The node must never die,
never publish NaN/inf on /gazebo/model_states or /gazebo/link_states, a refusal must name what
it refused, and a refused request must change nothing."""
import math
import os
import sys
import threading
import unittest

import rospy
import rostest
from gazebo_msgs.msg import LinkStates, ModelState, ModelStates
from geometry_msgs.msg import Pose, Vector3, Wrench

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo, fixture  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures"))
import fuzz_models as F  # noqa: E402

ARM = """<robot name='arm'><link name='world'/><link name='base'><inertial><mass value='2'/>
<inertia ixx='0.1' ixy='0' ixz='0' iyy='0.1' iyz='0' izz='0.1'/></inertial><collision><geometry>
<box size='0.2 0.2 0.2'/></geometry></collision></link><link name='tip'><inertial><mass value='0.5'/>
<inertia ixx='0.01' ixy='0' ixz='0' iyy='0.01' iyz='0' izz='0.01'/></inertial><collision><geometry>
<sphere radius='0.05'/></geometry></collision></link><link name='cap'><inertial><mass value='0.1'/>
<inertia ixx='0.001' ixy='0' ixz='0' iyy='0.001' iyz='0' izz='0.001'/></inertial></link>
<joint name='fix' type='fixed'><parent link='world'/><child link='base'/><origin xyz='0 0 0.1'/></joint>
<joint name='slide' type='prismatic'><parent link='base'/><child link='tip'/><origin xyz='0 0 0.3'/>
<axis xyz='1 0 0'/><limit lower='-0.5' upper='0.5' effort='20' velocity='1'/></joint>
<joint name='weld' type='fixed'><parent link='tip'/><child link='cap'/><origin xyz='0 0 0.1'/></joint>
</robot>"""


class Watch(object):
    """Every number published on a state topic must be finite."""

    def __init__(self):
        self.lock = threading.Lock()
        self.bad = []
        self.count = 0
        self.subs = [rospy.Subscriber("/gazebo/model_states", ModelStates, self._cb, queue_size=50),
                     rospy.Subscriber("/gazebo/link_states", LinkStates, self._cb, queue_size=50)]

    def _cb(self, msg):
        vals = []
        for p in msg.pose:
            vals += [p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y,
                     p.orientation.z, p.orientation.w]
        for t in msg.twist:
            vals += [t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z]
        with self.lock:
            self.count += 1
            if not all(math.isfinite(v) for v in vals):
                self.bad.append(list(msg.name))


def pose(x=0.0, y=0.0, z=0.0):
    p = Pose()
    p.position.x, p.position.y, p.position.z = x, y, z
    p.orientation.w = 1.0
    return p


class SimFuzz(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.gz = Gazebo()
        cls.watch = Watch()
        assert cls.gz.spawn("ground", "ground.urdf").success
        assert cls.gz.spawn("box", "box.urdf", z=0.5).success
        r = cls.gz.spawn_urdf_model(model_name="arm", model_xml=ARM, robot_namespace="",
                                    initial_pose=pose(2, 0, 0),
                                    reference_frame="")
        assert r.success, r.status_message
        cls.gz.unpause_physics()

    def alive(self):
        wp = self.gz.get_world_properties()
        self.assertTrue(wp.success)
        self.assertIn("arm", wp.model_names)
        return wp

    def physics(self):
        p = self.gz.get_physics_properties()
        return (p.time_step, p.gravity.x, p.gravity.y, p.gravity.z, p.ode_config.sor_pgs_w, p.ode_config.erp)

    def refused(self, r, *words):
        self.assertFalse(r.success, "accepted: %s" % r.status_message)
        for w in words:
            self.assertIn(w, r.status_message)

    def wrench(self, body, force, torque=(0, 0, 0), point=(0, 0, 0), duration=0.01):
        w = Wrench()
        w.force.x, w.force.y, w.force.z = force
        w.torque.x, w.torque.y, w.torque.z = torque
        p = Vector3(*point)
        return self.gz.apply_body_wrench(body_name=body, reference_frame="", reference_point=p, wrench=w,
                                         start_time=rospy.Time(0), duration=rospy.Duration(duration))

    # ---- the reproduced items ----------------------------------------------------------------------
    def test_1_absurd_lever_arm_and_physics_are_refused_and_change_nothing(self):
        self.refused(self.wrench("box::body", (0, 1e9, 0), point=(1e308, 0, 0)), "reference_point", "1e+06")
        before = self.physics()
        for g, dt, sor in (((0, 0, 1e308), 0.001, 1.3), ((0, 0, -9.8), 5e-324, 1.3),
                           ((0, 0, -3), 0.001, float("nan"))):
            req = self.gz.get_physics_properties()
            req.ode_config.sor_pgs_w = sor
            r = self.gz.set_physics_properties(time_step=dt, max_update_rate=0.0, gravity=Vector3(*g),
                                               ode_config=req.ode_config)
            self.refused(r, "nothing applied")
            self.assertEqual(self.physics(), before)
        self.alive()

    def test_2_positions_beyond_the_limit_are_refused(self):
        st = ModelState(model_name="box", pose=pose(9.9e8, 0, 0))
        self.refused(self.gz.set_model_state(model_state=st), "1e+06")
        r = self.gz.spawn_urdf_model(model_name="far", model_xml=fixture("box.urdf"), robot_namespace="",
                                     initial_pose=pose(1e12, 0, 0), reference_frame="")
        self.refused(r, "1e+06")
        r = self.gz.set_model_configuration(model_name="arm", urdf_param_name="", joint_names=["slide"],
                                            joint_positions=[1e12])
        self.refused(r, "slide", "1e+06")
        r = self.gz.set_model_configuration(model_name="arm", urdf_param_name="", joint_names=["slide"],
                                            joint_positions=[1e3])
        self.assertTrue(r.success, r.status_message)   # honoured: set to the upper limit
        js = self.gz.get_joint_properties(joint_name="arm::slide")
        self.assertLessEqual(js.position[0], 0.5 + 1e-6)
        self.alive()

    def test_3_effort_on_a_fixed_joint_is_refused_up_front_and_physics_keeps_running(self):
        r = self.gz.apply_joint_effort(joint_name="arm::weld", effort=1.0, start_time=rospy.Time(0),
                                       duration=rospy.Duration(-1))
        self.refused(r, "weld", "fixed")
        t0 = self.gz.sim_time()
        self.assertTrue(wait_until(lambda: self.gz.sim_time() > t0 + 0.05, 20.0), "physics stopped")

    # ---- random hostile requests -----------------------------------------------------------------
    def test_4_random_hostile_requests(self):
        fz = F.Fuzz(12, p_hostile=0.4)
        names = ("box", "arm", "slide", "link", "tip", "gravity", "time_step", "reference_point", "wrench",
                 "pose", "effort", "position", "ode_config", "max_update_rate", "nothing applied", "fixed",
                 "does not exist", "beyond", "NaN", "infinite", "finite")
        for i in range(25 * F.scale()):
            kind = fz.rng.randrange(6)
            by_field = True     # a refusal names the field: one of `names`
            if kind == 0:
                r = self.wrench(fz.rng.choice(["box::body", "arm::tip"]), fz.vec(-20, 20), fz.vec(-2, 2),
                                fz.vec(-0.2, 0.2), duration=0.01)
            elif kind == 1:
                p = fz.pose()
                st = ModelState(model_name="box", pose=pose(*p[0]))
                o = st.pose.orientation
                o.x, o.y, o.z, o.w = p[1]
                r = self.gz.set_model_state(model_state=st)
            elif kind == 2:
                r = self.gz.set_model_configuration(model_name="arm", urdf_param_name="",
                                                    joint_names=[fz.rng.choice(["slide", "weld"])],
                                                    joint_positions=[fz.num(-1, 1)])
            elif kind == 3:
                r = self.gz.apply_joint_effort(joint_name="arm::" + fz.rng.choice(["slide", "weld"]),
                                               effort=fz.num(-10, 10), start_time=rospy.Time(0),
                                               duration=rospy.Duration(0.01))
            elif kind == 4:
                req = self.gz.get_physics_properties()
                g = fz.vec(-12, 12)
                req.ode_config.erp = fz.num(0.1, 0.9)
                r = self.gz.set_physics_properties(time_step=fz.num(0.0005, 0.002), max_update_rate=0.0,
                                                   gravity=Vector3(*g), ode_config=req.ode_config)
            else:
                r = self.gz.spawn_urdf_model(model_name="fz%d" % i, model_xml=fz.urdf("fz%d" % i),
                                             robot_namespace="",
                                             initial_pose=pose(fz.rng.uniform(-3, 3), 3, 1),
                                             reference_frame="")
                if r.success:
                    self.gz.delete_model(model_name="fz%d" % i)
                else:   # names the model (then its link or joint and the element, in words of
                    self.assertIn("fz%d" % i, r.status_message)     # their own: not in `names`)
                by_field = False
            if not r.success and by_field:
                self.assertTrue(any(n in r.status_message for n in names), r.status_message)
            self.alive()
        # sane physics back, and the world still steps
        req = self.gz.get_physics_properties()
        req.ode_config.erp = 0.2
        r = self.gz.set_physics_properties(time_step=0.001, max_update_rate=0.0, gravity=Vector3(0, 0, -9.81),
                                           ode_config=req.ode_config)
        self.assertTrue(r.success, r.status_message)
        t0 = self.gz.sim_time()
        self.assertTrue(wait_until(lambda: self.gz.sim_time() > t0 + 0.05, 20.0), "physics stopped")
        n = self.watch.count
        self.assertTrue(wait_until(lambda: self.watch.count > n + 2, 20.0), "no state messages")
        with self.watch.lock:
            self.assertEqual(self.watch.bad, [], "NaN/inf published")


if __name__ == "__main__":
    rospy.init_node("sim_fuzz_test")
    rostest.rosrun("modrob_sim", "sim_fuzz", SimFuzz)
