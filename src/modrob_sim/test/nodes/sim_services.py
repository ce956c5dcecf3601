#!/usr/bin/env python3
"""rostest node: every /gazebo service called through rospy.ServiceProxy with gazebo_msgs types
(and modrob_msgs/StepSimulation), checked against what the physics must do."""
import copy
import math
import sys
import time
import unittest

import rospy
import rostest
from gazebo_msgs.msg import LinkStates, ModelState, ModelStates, PerformanceMetrics
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3, Wrench
from rosgraph_msgs.msg import Clock
from visualization_msgs.msg import MarkerArray

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo, Latest, fixture  # noqa: E402


class SimServices(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.gz = Gazebo()
        cls.clock = Latest("/clock", Clock)
        cls.models = Latest("/gazebo/model_states", ModelStates)
        cls.links = Latest("/gazebo/link_states", LinkStates)
        cls.gz.spawn("ground", "ground.urdf")

    def setUp(self):
        self.gz.pause_physics()
        for name in self.gz.get_world_properties().model_names:
            if name != "ground":
                self.gz.delete_model(model_name=name)

    def tearDown(self):
        self.gz.unpause_physics()

    # ---- spawn / state ------------------------------------------------------------------------
    def test_spawn_then_get_model_state_returns_spawn_pose(self):
        yaw = 0.7
        r = self.gz.spawn("box", "box.urdf", x=1.0, y=-2.0, z=0.5, qz=math.sin(yaw / 2), qw=math.cos(yaw / 2))
        self.assertTrue(r.success, r.status_message)
        s = self.gz.get_model_state(model_name="box", relative_entity_name="world")
        self.assertTrue(s.success, s.status_message)
        p, q = s.pose.position, s.pose.orientation
        self.assertAlmostEqual(p.x, 1.0, places=6)
        self.assertAlmostEqual(p.y, -2.0, places=6)
        self.assertAlmostEqual(p.z, 0.5, places=6)
        self.assertAlmostEqual(2 * math.atan2(q.z, q.w), yaw, places=6)
        self.assertEqual(s.header.frame_id, "world")

    def test_default_pose_quaternion_means_identity(self):
        r = self.gz.spawn_urdf_model(model_name="box", model_xml=fixture("box.urdf"), robot_namespace="",
                                     initial_pose=Pose(position=Point(0, 0, 0.3)), reference_frame="")
        self.assertTrue(r.success, r.status_message)
        q = self.gz.get_model_state(model_name="box", relative_entity_name="").pose.orientation
        self.assertAlmostEqual(q.w, 1.0, places=9)

    def test_state_relative_to_another_model_and_link(self):
        self.gz.spawn("box", "box.urdf", x=1.0, z=0.5)
        self.gz.spawn("arm2", "arm2.urdf", x=0.0, y=1.0)
        rel = self.gz.get_model_state(model_name="box", relative_entity_name="arm2")
        self.assertTrue(rel.success, rel.status_message)
        self.assertAlmostEqual(rel.pose.position.x, 1.0, places=6)
        self.assertAlmostEqual(rel.pose.position.y, -1.0, places=6)
        link = self.gz.get_link_state(link_name="box::body", reference_frame="arm2::base")
        self.assertTrue(link.success, link.status_message)
        self.assertAlmostEqual(link.link_state.pose.position.y, -1.0, places=6)
        bad = self.gz.get_model_state(model_name="box", relative_entity_name="nothing::here")
        self.assertFalse(bad.success)
        self.assertIn("nothing::here", bad.status_message)
        missing = self.gz.get_model_state(model_name="nobody", relative_entity_name="")
        self.assertFalse(missing.success)
        self.assertIn("nobody", missing.status_message)

    def test_spawn_relative_to_reference_frame(self):
        self.gz.spawn("arm2", "arm2.urdf", x=2.0)
        r = self.gz.spawn("box", "box.urdf", z=1.0, frame="arm2::base")
        self.assertTrue(r.success, r.status_message)
        s = self.gz.get_model_state(model_name="box", relative_entity_name="world")
        self.assertAlmostEqual(s.pose.position.x, 2.0, places=6)
        self.assertAlmostEqual(s.pose.position.z, 1.0, places=6)

    def test_delete_model_removes_it_from_model_states(self):
        self.gz.spawn("box", "box.urdf", z=0.5)
        self.gz.unpause_physics()
        self.assertTrue(wait_until(lambda: self.models.get() and "box" in self.models.get().name, 20.0))
        self.assertTrue(wait_until(lambda: self.links.get() and "box::body" in self.links.get().name, 20.0))
        r = self.gz.delete_model(model_name="box")
        self.assertTrue(r.success, r.status_message)
        t0 = self.models.count
        self.assertTrue(wait_until(lambda: self.models.count > t0 + 1 and "box" not in self.models.get().name,
                                   20.0))
        self.assertNotIn("box", self.gz.get_world_properties().model_names)
        again = self.gz.delete_model(model_name="box")
        self.assertFalse(again.success)
        self.assertIn("box", again.status_message)

    def test_set_model_state_service_and_topic_while_running(self):
        self.gz.spawn("box", "box.urdf", z=0.1)
        self.gz.unpause_physics()
        st = ModelState(model_name="box", pose=Pose(Point(0.5, 0.5, 0.1), Quaternion(0, 0, 0, 1)),
                        twist=Twist(), reference_frame="world")
        r = self.gz.set_model_state(model_state=st)
        self.assertTrue(r.success, r.status_message)
        s = self.gz.get_model_state(model_name="box", relative_entity_name="world")
        self.assertAlmostEqual(s.pose.position.x, 0.5, places=2)
        pub = rospy.Publisher("/gazebo/set_model_state", ModelState, queue_size=1)
        st.pose.position.x = -0.7
        self.assertTrue(wait_until(lambda: pub.publish(st) or abs(self.gz.get_model_state(
            model_name="box", relative_entity_name="").pose.position.x + 0.7) < 0.01, 10.0, period=0.2))
        nan = ModelState(model_name="box", pose=Pose(Point(float("nan"), 0, 0), Quaternion(0, 0, 0, 1)))
        r = self.gz.set_model_state(model_state=nan)
        self.assertFalse(r.success)
        self.assertIn("NaN", r.status_message)

    def test_set_link_state(self):
        self.gz.spawn("box", "box.urdf", z=0.1)
        ls = self.gz.get_link_state(link_name="box::body", reference_frame="").link_state
        ls.pose.position.z = 0.8
        r = self.gz.set_link_state(link_state=ls)
        self.assertTrue(r.success, r.status_message)
        got = self.gz.get_link_state(link_name="box::body", reference_frame="world")
        self.assertAlmostEqual(got.link_state.pose.position.z, 0.8, places=6)
        self.assertFalse(self.gz.get_link_state(link_name="box::nolink", reference_frame="").success)

    def test_set_model_configuration_while_running(self):
        self.gz.spawn("arm2", "arm2.urdf")
        self.gz.unpause_physics()
        r = self.gz.set_model_configuration(model_name="arm2", urdf_param_name="",
                                            joint_names=["shoulder", "elbow"], joint_positions=[0.5, -0.4])
        self.assertTrue(r.success, r.status_message)
        self.gz.pause_physics()
        sh = self.gz.get_joint_properties(joint_name="shoulder")
        self.assertTrue(sh.success, sh.status_message)
        self.assertEqual(sh.type, sh.REVOLUTE)
        self.assertAlmostEqual(sh.position[0], 0.5, delta=0.05)
        bad = self.gz.set_model_configuration(model_name="arm2", urdf_param_name="", joint_names=["knee"],
                                              joint_positions=[1.0])
        self.assertFalse(bad.success)
        self.assertIn("knee", bad.status_message)

    # ---- properties ---------------------------------------------------------------------------
    def test_properties(self):
        self.gz.spawn("arm2", "arm2.urdf")
        mp = self.gz.get_model_properties(model_name="arm2")
        self.assertTrue(mp.success, mp.status_message)
        self.assertEqual(set(mp.joint_names), {"shoulder", "elbow"})
        self.assertTrue({"upper", "fore"} <= set(mp.body_names))
        self.assertFalse(mp.is_static)
        lp = self.gz.get_link_properties(link_name="arm2::upper")
        self.assertTrue(lp.success, lp.status_message)
        self.assertAlmostEqual(lp.mass, 0.5)
        self.assertAlmostEqual(lp.com.position.z, 0.15)
        self.assertTrue(lp.gravity_mode)
        r = self.gz.set_link_properties(link_name="arm2::upper", com=lp.com, gravity_mode=False,
                                        mass=lp.mass, ixx=lp.ixx, ixy=lp.ixy, ixz=lp.ixz, iyy=lp.iyy,
                                        iyz=lp.iyz, izz=lp.izz)
        self.assertTrue(r.success, r.status_message)
        self.assertFalse(self.gz.get_link_properties(link_name="arm2::upper").gravity_mode)
        wp = self.gz.get_world_properties()
        self.assertTrue(wp.success)
        self.assertIn("arm2", wp.model_names)
        jp = self.gz.get_joint_properties(joint_name="arm2::elbow")
        self.assertTrue(jp.success, jp.status_message)
        self.assertFalse(self.gz.get_joint_properties(joint_name="nojoint").success)

    def test_physics_properties_round_trip(self):
        orig = self.gz.get_physics_properties()
        self.assertTrue(orig.success)
        self.assertAlmostEqual(orig.time_step, 0.001)
        self.assertTrue(orig.pause)
        self.assertEqual(orig.ode_config.sor_pgs_iters, 50)
        r = self.gz.set_physics_properties(time_step=orig.time_step, max_update_rate=orig.max_update_rate,
                                           gravity=Vector3(0, 0, -1.62), ode_config=orig.ode_config)
        self.assertTrue(r.success, r.status_message)
        self.assertAlmostEqual(self.gz.get_physics_properties().gravity.z, -1.62)
        r = self.gz.set_physics_properties(time_step=orig.time_step, max_update_rate=orig.max_update_rate,
                                           gravity=orig.gravity, ode_config=orig.ode_config)
        self.assertTrue(r.success, r.status_message)
        bad = self.gz.set_physics_properties(time_step=-1.0, max_update_rate=0.0, gravity=orig.gravity,
                                             ode_config=orig.ode_config)
        self.assertFalse(bad.success)
        self.assertIn("time_step", bad.status_message)
        # an early-exit tolerance (Gazebo's ODE fork) cannot be honoured: the rest is applied and
        # the reply says what was not, instead of dropping it without a word
        cfg = copy.deepcopy(orig.ode_config)
        cfg.sor_pgs_rms_error_tol = 1e-6
        cfg.sor_pgs_iters = 40
        r = self.gz.set_physics_properties(time_step=orig.time_step, max_update_rate=orig.max_update_rate,
                                           gravity=orig.gravity, ode_config=cfg)
        self.assertTrue(r.success, r.status_message)
        self.assertIn("not applied: sor_pgs_rms_error_tol 1e-06", r.status_message)
        self.assertEqual(self.gz.get_physics_properties().ode_config.sor_pgs_iters, 40)
        self.assertEqual(self.gz.get_physics_properties().ode_config.sor_pgs_rms_error_tol, 0.0)
        r = self.gz.set_physics_properties(time_step=orig.time_step, max_update_rate=orig.max_update_rate,
                                           gravity=orig.gravity, ode_config=orig.ode_config)
        self.assertTrue(r.success, r.status_message)
        self.assertNotIn("not applied", r.status_message)

    # ---- time --------------------------------------------------------------------------------
    def test_pause_stops_clock_and_unpause_restarts_it(self):
        self.gz.unpause_physics()
        self.assertTrue(wait_until(lambda: self.clock.get() is not None, 20.0))
        self.gz.pause_physics()
        # the clock messages still on their way (at real_time_factor 0 a simulated second of them
        # can be) have arrived once the latest is the paused simulator's time
        paused_at = self.gz.sim_time()
        self.assertTrue(wait_until(lambda: abs(self.clock.get().clock.to_sec() - paused_at) < 1e-6, 10.0),
                        "/clock never reached the paused time %.3f (at %.3f)"
                        % (paused_at, self.clock.get().clock.to_sec()))
        frozen = self.clock.get().clock
        n = self.clock.count
        time.sleep(0.5)
        self.assertEqual(self.clock.get().clock, frozen)
        self.assertEqual(self.clock.count, n)
        self.gz.unpause_physics()
        self.assertTrue(wait_until(lambda: self.clock.get().clock > frozen, 10.0))

    def test_step_advances_exactly_n_steps(self):
        it0 = self.gz.iterations()
        r = self.gz.step(steps=250)
        self.assertTrue(r.success, r.status_message)
        self.assertEqual(r.iterations, it0 + 250)
        self.assertEqual(self.gz.iterations(), it0 + 250)
        self.assertTrue(wait_until(lambda: abs(self.clock.get().clock.to_sec() - r.sim_time) < 1e-6, 5.0))
        self.gz.unpause_physics()
        refused = self.gz.step(steps=1)
        self.assertFalse(refused.success)
        self.assertIn("pause_physics", refused.status_message)

    def test_reset_simulation_restores_poses_and_time(self):
        self.gz.spawn("box", "box.urdf", x=0.3, z=1.0)
        self.gz.step(steps=600)
        fallen = self.gz.get_model_state(model_name="box", relative_entity_name="").pose.position.z
        self.assertLess(fallen, 0.5)
        self.gz.reset_simulation()
        s = self.gz.get_model_state(model_name="box", relative_entity_name="")
        self.assertAlmostEqual(s.pose.position.z, 1.0, places=6)
        self.assertAlmostEqual(s.pose.position.x, 0.3, places=6)
        self.assertEqual(self.gz.iterations(), 0)
        self.assertAlmostEqual(self.gz.sim_time(), 0.0)

    def test_reset_world_keeps_time(self):
        self.gz.spawn("box", "box.urdf", z=1.0)
        self.gz.step(steps=400)
        t = self.gz.sim_time()
        self.gz.reset_world()
        s = self.gz.get_model_state(model_name="box", relative_entity_name="")
        self.assertAlmostEqual(s.pose.position.z, 1.0, places=6)
        self.assertAlmostEqual(self.gz.sim_time(), t, places=6)

    # ---- forces ------------------------------------------------------------------------------
    def test_body_wrench_with_duration_lifts_then_stops(self):
        self.gz.spawn("box", "box.urdf", z=0.1)
        self.gz.step(steps=200)                                   # settle on the ground
        r = self.gz.apply_body_wrench(body_name="box::body", reference_frame="world", reference_point=Point(),
                                      wrench=Wrench(force=Vector3(0, 0, 29.81)), start_time=rospy.Time(0),
                                      duration=rospy.Duration(0.5))
        self.assertTrue(r.success, r.status_message)
        self.gz.step(steps=500)                                   # net 20 N up on 1 kg for 0.5 s
        s = self.gz.get_model_state(model_name="box", relative_entity_name="")
        self.assertGreater(s.twist.linear.z, 8.0)
        self.gz.step(steps=300)                                   # force over: decelerates at g
        s2 = self.gz.get_model_state(model_name="box", relative_entity_name="")
        self.assertLess(s2.twist.linear.z, s.twist.linear.z - 2.0)
        forever = self.gz.apply_body_wrench(body_name="box::body", reference_frame="",
                                            reference_point=Point(), wrench=Wrench(force=Vector3(5, 0, 0)),
                                            start_time=rospy.Time(0), duration=rospy.Duration(-1))
        self.assertTrue(forever.success, forever.status_message)
        self.gz.clear_body_wrenches(body_name="box::body")
        bad = self.gz.apply_body_wrench(body_name="box::nothing", reference_frame="", reference_point=Point(),
                                        wrench=Wrench(), start_time=rospy.Time(0), duration=rospy.Duration(1))
        self.assertFalse(bad.success)

    def test_joint_effort_start_time_and_duration(self):
        self.gz.spawn("arm2", "arm2.urdf")
        t0 = self.gz.sim_time()
        r = self.gz.apply_joint_effort(joint_name="shoulder", effort=0.5,
                                       start_time=rospy.Time.from_sec(t0 + 0.1), duration=rospy.Duration(0.2))
        self.assertTrue(r.success, r.status_message)
        self.gz.step(steps=90)
        self.assertAlmostEqual(self.gz.get_joint_properties(joint_name="shoulder").rate[0], 0.0, places=6)
        self.gz.step(steps=210)                                    # t0+0.3: effort over
        v1 = self.gz.get_joint_properties(joint_name="shoulder").rate[0]
        self.assertGreater(v1, 0.05)
        self.gz.step(steps=100)
        v2 = self.gz.get_joint_properties(joint_name="shoulder").rate[0]
        self.assertLessEqual(v2, v1 + 1e-9)                        # damping only: no more push
        r = self.gz.apply_joint_effort(joint_name="shoulder", effort=0.5, start_time=rospy.Time(0),
                                       duration=rospy.Duration(-1))
        self.assertTrue(r.success)
        self.gz.clear_joint_forces(joint_name="shoulder")
        self.gz.step(steps=100)
        self.assertLessEqual(self.gz.get_joint_properties(joint_name="shoulder").rate[0], v2 + 1e-9)

    # ---- topics ------------------------------------------------------------------------------
    def test_performance_metrics_and_world_markers(self):
        self.gz.spawn("box", "box.urdf", z=0.5)
        self.gz.unpause_physics()
        perf = Latest("/gazebo/performance_metrics", PerformanceMetrics)
        self.assertTrue(wait_until(lambda: perf.get() is not None, 10.0))
        self.assertGreater(perf.get().real_time_factor, 0.0)
        markers = Latest("/gazebo/world_markers", MarkerArray)
        self.assertTrue(wait_until(lambda: markers.get() is not None and any(
            m.ns == "box" for m in markers.get().markers), 10.0))
        self.assertTrue(any(m.ns == "ground" for m in markers.get().markers))
        self.assertFalse(any(m.ns == "arm2" for m in markers.get().markers))

    def test_world_markers_follow_a_teleport_while_paused(self):
        # RViz shows the world through the latched ~world_markers: a model moved while the
        # simulation is paused must be drawn where it now is, also for a subscriber that comes later
        self.gz.spawn("box", "box.urdf", z=0.5)
        pose = Pose(position=Point(1.5, -1.0, 0.7), orientation=Quaternion(0, 0, 0, 1))
        state = ModelState(model_name="box", pose=pose, reference_frame="world")
        r = self.gz.set_model_state(model_state=state)
        self.assertTrue(r.success, r.status_message)
        markers = Latest("/gazebo/world_markers", MarkerArray)

        def box_markers():
            msg = markers.get()
            return [m for m in msg.markers if m.ns == "box"] if msg is not None else []

        # the first message may be one this process had already received (rospy hands a new
        # subscriber the last message of its open connection), so wait for the teleported box
        moved = wait_until(lambda: box_markers() and all(
            abs(m.pose.position.x - 1.5) < 1e-3 and abs(m.pose.position.y + 1.0) < 1e-3
            and abs(m.pose.position.z - 0.7) < 1e-3 for m in box_markers()), 10.0)
        where = [(m.pose.position.x, m.pose.position.y, m.pose.position.z) for m in box_markers()]
        self.assertTrue(moved, "box markers at %s" % where)
        markers.sub.unregister()

    def test_use_sim_time_is_set(self):
        self.assertTrue(rospy.get_param("/use_sim_time"))


if __name__ == "__main__":
    rospy.init_node("sim_services_test")
    rostest.rosrun("modrob_sim", "sim_services", SimServices)
