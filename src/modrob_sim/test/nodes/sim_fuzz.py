#!/usr/bin/env python3
"""rostest node: hostile requests against /gazebo (seeded; MODROB_FUZZ_SCALE scales the random
part). Each reproduced request of issue 12 first, then random ones; then FollowJointTrajectory
goals with hostile tolerances to an effort JointTrajectoryController (whose path tolerances the
joints' actuators watch) among cancels, preemptions, controller switches and world resets; then
cmd_vel_out subscribers of a DiffDriveController that come and go at once. The node must never
die, never publish NaN/inf on /gazebo/model_states or /gazebo/link_states, a refusal must name what
it refused, a refused request must change nothing, and every goal gets its result."""
import collections
import math
import os
import sys
import threading
import unittest

import actionlib
import rospy
import rostest
import yaml
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryActionResult,
                              FollowJointTrajectoryGoal, JointTolerance)
from controller_manager_msgs.srv import LoadController, SwitchController
from gazebo_msgs.msg import LinkStates, ModelState, ModelStates
from geometry_msgs.msg import Pose, Twist, TwistStamped, Vector3, Wrench
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo, fixture  # noqa: E402

FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")
sys.path.insert(0, FIXTURES)
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


# the 3-joint arm with effort joints under two effort trajectory controllers (switched in turn)
ARM3_NS = "/fz_arm"
ARM3_JOINTS = ["yaw", "shoulder", "elbow"]
ARM3_GAINS = {"yaw": {"p": 80.0, "i": 30.0, "d": 1.5, "i_clamp": 5.0},
              "shoulder": {"p": 200.0, "i": 50.0, "d": 10.0, "i_clamp": 8.0},
              "elbow": {"p": 120.0, "d": 6.0}}
ARM3_JTC = {"type": "effort_controllers/JointTrajectoryController", "joints": ARM3_JOINTS,
            "gains": ARM3_GAINS,
            "state_publish_rate": 25, "action_monitor_rate": 10, "stop_trajectory_duration": 0.1,
            "constraints": {"goal_time": 0.5, "stopped_velocity_tolerance": 0.2,
                            "shoulder": {"trajectory": 0.5, "goal": 0.1}, "elbow": {"goal": 0.1}}}
#: a goal's terminal states (actionlib)
DONE = (GoalStatus.PREEMPTED, GoalStatus.SUCCEEDED, GoalStatus.ABORTED, GoalStatus.REJECTED,
        GoalStatus.RECALLED)


def finite_message(values):
    return all(math.isfinite(v) for v in values)


def load_and_start(ns, names, loaded=()):
    """Load the controllers ``names`` and ``loaded`` (their parameters set already) in ``ns`` and
    start ``names``. Returns the switch_controller service."""
    rospy.wait_for_service(ns + "/controller_manager/load_controller", 30.0)
    load = rospy.ServiceProxy(ns + "/controller_manager/load_controller", LoadController)
    for n in list(names) + list(loaded):
        assert load(name=n).ok, "%s: loading %s failed" % (ns, n)
    switch = rospy.ServiceProxy(ns + "/controller_manager/switch_controller", SwitchController)
    assert switch(start_controllers=names, stop_controllers=[], strictness=2).ok
    return switch


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
        with open(os.path.join(FIXTURES, "control", "arm_3dof.urdf")) as f:
            arm3 = f.read().replace("PositionJointInterface", "EffortJointInterface")
        arm3 = arm3.replace("/arm3", ARM3_NS)
        rospy.set_param(ARM3_NS + "/joint_state_controller",
                        {"type": "joint_state_controller/JointStateController", "publish_rate": 50})
        rospy.set_param(ARM3_NS + "/jtc_a", ARM3_JTC)
        rospy.set_param(ARM3_NS + "/jtc_b", ARM3_JTC)
        r = cls.gz.spawn_urdf_model(model_name="fz_arm", model_xml=arm3, robot_namespace=ARM3_NS,
                                    initial_pose=pose(-2.5, 2.5, 0), reference_frame="")
        assert r.success, r.status_message
        with open(os.path.join(FIXTURES, "control", "diffbot_control.yaml")) as f:
            for name, values in yaml.safe_load(f).items():
                rospy.set_param("/" + name, values)
        with open(os.path.join(FIXTURES, "control", "diffbot.urdf")) as f:
            r = cls.gz.spawn_urdf_model(model_name="diffbot", model_xml=f.read(), robot_namespace="",
                                        initial_pose=pose(-1.0, -1.0, 0.1), reference_frame="")
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

    # ---- a trajectory controller's goals, watched by the joints' actuators -----------------------
    def hostile_goal(self, fz):
        """A goal of 1-3 points within the joints' limits, with tolerances drawn by ``fz`` (NaN,
        infinite, negative, tiny, huge among them). Returns (goal, its tolerances are finite)."""
        g = FollowJointTrajectoryGoal()
        g.trajectory.joint_names = list(ARM3_JOINTS)
        t = 0.0
        for _ in range(fz.rng.randint(1, 3)):
            t += fz.rng.uniform(0.1, 0.6)
            positions = [fz.rng.uniform(-1.0, 1.0) for _ in ARM3_JOINTS]
            g.trajectory.points.append(JointTrajectoryPoint(positions=positions,
                                                            time_from_start=rospy.Duration(t)))
        g.trajectory.points[-1].velocities = [0.0] * len(ARM3_JOINTS)
        for tols in (g.path_tolerance, g.goal_tolerance):
            for j in ARM3_JOINTS:
                if fz.rng.random() < 0.6:
                    tols.append(JointTolerance(name=j, position=fz.num(0.05, 1.0),
                                               velocity=fz.num(0.5, 5.0) if fz.rng.random() < 0.3 else 0.0))
        g.goal_time_tolerance = rospy.Duration(fz.rng.choice([0.0, 0.2, 1.0, -1.0, 1e4]))
        finite = finite_message([v for tol in g.path_tolerance + g.goal_tolerance
                                 for v in (tol.position, tol.velocity)])
        return g, finite

    def test_5_trajectory_goals_with_hostile_tolerances_among_cancels_switches_and_resets(self):
        """Goals (most with path tolerances: bands on the joints' actuators) replaced, cancelled, their
        controller switched off, the simulation or the world reset while they run; every goal gets
        its result (on the result topic: at real_time_factor 0 a client's status array can drop a
        goal the server has finished), one with a NaN/inf tolerance is rejected naming it."""
        fz = F.Fuzz(15, p_hostile=0.25)
        switch = load_and_start(ARM3_NS, ["joint_state_controller", "jtc_a"], loaded=["jtc_b"])
        clients, results = {}, {}

        def result(m):
            results[m.status.goal_id.id] = (m.status.status, m.result.error_string)
        for n in ("jtc_a", "jtc_b"):
            action = "%s/%s/follow_joint_trajectory" % (ARM3_NS, n)
            clients[n] = actionlib.ActionClient(action, FollowJointTrajectoryAction)
            rospy.Subscriber(action + "/result", FollowJointTrajectoryActionResult, result, queue_size=None)
            self.assertTrue(wait_until(lambda: clients[n].wait_for_server(rospy.Duration(0.05)), 30.0), n)
        joint_states = []
        sub = rospy.Subscriber(ARM3_NS + "/joint_states", JointState, lambda m: joint_states.append(
            finite_message(list(m.position) + list(m.velocity))), queue_size=50)
        running, stopped = "jtc_a", "jtc_b"
        sent = []       # (goal id, goal handle, to the running controller, its tolerances are finite)
        plan = []
        for _ in range(2 * F.scale()):      # every kind in each round, in a seeded order
            rnd = ["goal"] * 6 + ["cancel", "cancel", "switch", "reset_simulation", "reset_world"]
            fz.rng.shuffle(rnd)
            plan += rnd
        for kind in plan:
            if kind == "goal":      # a new goal preempts the one in progress (the band it had is dropped)
                to = running if fz.rng.random() < 0.9 else stopped
                g, finite = self.hostile_goal(fz)
                gh = clients[to].send_goal(g)
                sent.append((gh.comm_state_machine.action_goal.goal_id.id, gh, to == running, finite))
            elif kind == "cancel" and sent:
                sent[-1][1].cancel()
            elif kind == "switch":
                r = switch(start_controllers=[stopped], stop_controllers=[running], strictness=2)
                self.assertTrue(r.ok)
                running, stopped = stopped, running
            elif kind in ("reset_simulation", "reset_world"):
                getattr(self.gz, kind)()
            t0 = self.gz.sim_time()
            wait = fz.rng.choice([0.0, 0.01, 0.05, 0.3])
            self.assertTrue(wait_until(lambda: self.gz.sim_time() >= t0 + wait, 20.0), "physics stopped")
            self.alive()
        for _, gh, _, _ in sent:
            gh.cancel()
        for k, (gid, gh, to_running, finite) in enumerate(sent):
            self.assertTrue(wait_until(lambda: gid in results, 30.0), "goal %d got no result" % k)
            status, text = results[gid]
            self.assertIn(status, DONE)
            if not finite:      # never accepted: refused up front, naming the tolerance and its joint
                # (or recalled: its cancel reached the server before the goal did)
                self.assertIn(status, (GoalStatus.REJECTED, GoalStatus.RECALLED),
                              "goal %d with a NaN/inf tolerance: %s" % (k, text))
                if status == GoalStatus.REJECTED:
                    self.assertTrue("tolerance of joint '" in text or "not running" in text, text)
            elif status == GoalStatus.REJECTED:     # only by a controller that was stopped
                self.assertIn("not running", text)
        self.assertTrue(any(not s[3] for s in sent) and any(s[3] for s in sent), "both kinds of goal")
        # the running controller still follows a goal to its end
        g = FollowJointTrajectoryGoal()
        g.trajectory.joint_names = list(ARM3_JOINTS)
        g.trajectory.points.append(JointTrajectoryPoint(positions=[0.2, 0.1, -0.2], velocities=[0.0] * 3,
                                                        time_from_start=rospy.Duration(0.5)))
        g.path_tolerance = [JointTolerance(name="shoulder", position=1.0)]
        gh = clients[running].send_goal(g)
        gid = gh.comm_state_machine.action_goal.goal_id.id
        self.assertTrue(wait_until(lambda: gid in results, 30.0), "the last goal got no result")
        self.assertEqual(results[gid][0], GoalStatus.SUCCEEDED, results[gid][1])
        sub.unregister()
        self.assertTrue(joint_states and all(joint_states), "no or non-finite joint states")
        rospy.loginfo("sim_fuzz: %d trajectory goals (%d with a NaN/inf tolerance): %s" % (
            len(sent), sum(1 for s in sent if not s[3]),
            dict(collections.Counter(s for s, _ in results.values()))))

    # ---- a mobile base's cmd_vel_out: subscribers that come and go --------------------------------
    def test_6_cmd_vel_out_subscribers_come_and_go_among_hostile_commands(self):
        fz = F.Fuzz(16, p_hostile=0.2)
        load_and_start("", ["diffbot_joint_publisher", "diffbot_velocity_controller"])
        ns = "/diffbot_velocity_controller"
        out, odom = [], []
        cmd = rospy.Publisher(ns + "/cmd_vel", Twist, queue_size=10)
        rospy.Subscriber(ns + "/odom", Odometry, lambda m: odom.append(finite_message(
            [m.pose.pose.position.x, m.pose.pose.position.y, m.twist.twist.linear.x,
             m.twist.twist.angular.z])), queue_size=50)
        subs = []
        for _ in range(25 * F.scale()):
            r = fz.rng.random()
            if r < 0.4:
                subs.append(rospy.Subscriber(ns + "/cmd_vel_out", TwistStamped, lambda m: out.append(
                    finite_message([m.twist.linear.x, m.twist.angular.z])), queue_size=10))
            elif r < 0.8 and subs:
                subs.pop(fz.rng.randrange(len(subs))).unregister()
            else:
                cmd.publish(Twist(linear=Vector3(fz.num(-0.3, 0.3), 0, 0),
                                  angular=Vector3(0, 0, fz.num(-1, 1))))
            t0 = self.gz.sim_time()
            wait = fz.rng.choice([0.0, 0.0, 0.002, 0.05, 0.15])
            self.assertTrue(wait_until(lambda: self.gz.sim_time() >= t0 + wait, 20.0), "physics stopped")
        for s in subs:
            s.unregister()
        # one that stays: its messages come (within IDLE_LOOK of simulated time, then at every update)
        n = len(out)
        stay = rospy.Subscriber(ns + "/cmd_vel_out", TwistStamped, lambda m: out.append(
            finite_message([m.twist.linear.x, m.twist.angular.z])), queue_size=10)
        self.assertTrue(wait_until(lambda: len(out) > n + 20, 30.0),
                        "no cmd_vel_out for a subscriber that stays")
        stay.unregister()
        self.assertTrue(all(out), "a non-finite cmd_vel_out")
        self.assertTrue(odom and all(odom), "no or non-finite odometry")
        self.alive()
        with self.watch.lock:
            self.assertEqual(self.watch.bad, [], "NaN/inf published")


if __name__ == "__main__":
    rospy.init_node("sim_fuzz_test")
    rostest.rosrun("modrob_sim", "sim_fuzz", SimFuzz)
