#!/usr/bin/env python3
"""rostest node: bad input gets success: false with a message naming the problem, an unstable
model trips the blow-up guard (reported with model and link), and /gazebo keeps answering."""
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import Pose
from std_msgs.msg import String

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo, fixture  # noqa: E402


class SimBadInput(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.gz = Gazebo()
        cls.guard_events = []
        cls.guard = rospy.Subscriber("/gazebo/guard_events", String,
                                     lambda m: cls.guard_events.append(m.data), queue_size=100)
        assert cls.gz.spawn("ground", "ground.urdf").success   # nothing else falls for ever

    def still_serving(self):
        wp = self.gz.get_world_properties()
        self.assertTrue(wp.success)
        return wp

    def spawn_text(self, name, text):
        return self.gz.spawn_urdf_model(model_name=name, model_xml=text, robot_namespace="",
                                        initial_pose=Pose(), reference_frame="")

    def test_malformed_urdf(self):
        r = self.spawn_text("broken", fixture("malformed.urdf"))
        self.assertFalse(r.success)
        self.assertIn("broken", r.status_message)
        self.assertIn("not valid XML", r.status_message)
        self.assertNotIn("broken", self.still_serving().model_names)

    def test_not_a_robot_description(self):
        r = self.spawn_text("html", "<html><body/></html>")
        self.assertFalse(r.success)
        self.assertIn("neither URDF", r.status_message)

    def test_empty_xml(self):
        r = self.spawn_text("empty", "  ")
        self.assertFalse(r.success)
        self.assertIn("empty", r.status_message)
        self.still_serving()

    def test_unknown_mesh(self):
        r = self.spawn_text("ghost", fixture("unknown_mesh.urdf"))
        self.assertFalse(r.success)
        self.assertIn("no_such_mesh.stl", r.status_message)
        self.assertNotIn("ghost", self.still_serving().model_names)

    def test_duplicate_name(self):
        first = self.gz.spawn("dup", "box.urdf", x=3.0, z=0.2)
        self.assertTrue(first.success, first.status_message)
        again = self.gz.spawn("dup", "box.urdf", x=5.0, z=0.2)
        self.assertFalse(again.success)
        self.assertIn("dup", again.status_message)
        self.assertIn("already exists", again.status_message)
        s = self.gz.get_model_state(model_name="dup", relative_entity_name="")
        self.assertAlmostEqual(s.pose.position.x, 3.0, places=3)   # the first one is untouched

    def test_urdf_semantic_error_names_the_link(self):
        text = fixture("box.urdf").replace('<mass value="1.0"/>', '<mass value="-1.0"/>')
        r = self.spawn_text("negative_mass", text)
        self.assertFalse(r.success)
        self.assertIn("negative_mass", r.status_message)
        self.still_serving()

    def test_unsupported_gazebo_services_answer_with_the_reason(self):
        from gazebo_msgs.srv import DeleteLight, SetJointProperties
        from gazebo_msgs.msg import ODEJointProperties
        rospy.wait_for_service("/gazebo/delete_light", 10)
        r = rospy.ServiceProxy("/gazebo/delete_light", DeleteLight)(light_name="sun")
        self.assertFalse(r.success)
        self.assertIn("not supported", r.status_message)
        r = rospy.ServiceProxy("/gazebo/set_joint_properties", SetJointProperties)(
            joint_name="shoulder", ode_joint_config=ODEJointProperties(damping=[1.0]))
        self.assertFalse(r.success)
        self.assertIn("shoulder", r.status_message)
        self.still_serving()

    def test_unstable_model_trips_the_guard_and_node_stays_up(self):
        r = self.gz.spawn("unstable", "unstable.urdf")
        self.assertTrue(r.success, r.status_message)
        self.gz.unpause_physics()
        e = self.gz.apply_joint_effort(joint_name="unstable::slide", effort=1e6, start_time=rospy.Time(0),
                                       duration=rospy.Duration(0.05))
        self.assertTrue(e.success, e.status_message)
        mine = lambda: [t for t in self.guard_events if "model=unstable" in t]  # noqa: E731
        self.assertTrue(wait_until(mine, 20.0),
                        "no guard event for the unstable model: %s" % self.guard_events)
        self.assertIn("link=feather", mine()[0])
        self.assertIn("runaway", mine()[0])
        self.still_serving()
        t0 = self.gz.sim_time()
        self.assertTrue(wait_until(lambda: self.gz.sim_time() > t0 + 0.1, 10.0), "simulation stopped")
        s = self.gz.get_link_state(link_name="unstable::feather", reference_frame="world").link_state
        self.assertLess(abs(s.pose.position.x), 1000.0)
        self.assertLess(abs(s.twist.linear.x), 1e3)
        self.still_serving()   # and answers after the restore

    def test_z_a_model_that_keeps_blowing_up_is_frozen_alone_until_set_model_state(self):
        from gazebo_msgs.msg import ModelState
        r = self.gz.spawn("runaway", "unstable.urdf", y=3.0)
        self.assertTrue(r.success, r.status_message)
        self.gz.unpause_physics()
        e = self.gz.apply_joint_effort(joint_name="runaway::slide", effort=1e6, start_time=rospy.Time(0),
                                       duration=rospy.Duration(-1))   # until cleared: every step blows up
        self.assertTrue(e.success, e.status_message)
        mine = lambda: [t for t in self.guard_events if "model=runaway " in t]  # noqa: E731
        frozen = lambda: [t for t in mine() if t.endswith("reason=frozen")]  # noqa: E731
        self.assertTrue(wait_until(frozen, 60.0), "never frozen: %d events" % len(mine()))
        # the rest of the world goes on: physics not paused, time advances, no more events of it
        self.assertFalse(self.gz.get_physics_properties().pause)
        n, t0 = len(mine()), self.gz.sim_time()
        self.assertTrue(wait_until(lambda: self.gz.sim_time() > t0 + 0.3, 20.0), "simulation stopped")
        self.assertEqual(len(mine()), n, "a frozen model was still restored: %s" % mine()[n:])
        # set_model_state releases it (the effort still runs: it blows up again, now reported)
        state = ModelState(model_name="runaway")
        state.pose.position.y = 3.0
        state.pose.orientation.w = 1.0
        self.assertTrue(self.gz.set_model_state(model_state=state).success)
        self.assertTrue(wait_until(lambda: len(mine()) > n, 20.0), "not released by set_model_state")
        self.assertTrue(self.gz.delete_model(model_name="runaway").success)
        self.still_serving()


if __name__ == "__main__":
    rospy.init_node("sim_bad_input_test")
    rostest.rosrun("modrob_sim", "sim_bad_input", SimBadInput)
