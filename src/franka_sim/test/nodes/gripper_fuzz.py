#!/usr/bin/env python3
"""rostest node: hostile franka_gripper goals against FrankaGripperSim on the Panda-style test arm
(seeded with modrob_sim's fuzz generators; MODROB_FUZZ_SCALE scales it). Move, grasp and
gripper_action goals whose width, speed, force or epsilon are drawn sane or hostile (zero,
negative, tiny, huge, NaN, infinite), among stops, cancels and world resets while a goal runs.
Every goal gets its result; one with a NaN or infinite value never succeeds and its error names
the value; the fingers' joint states stay finite and /gazebo keeps stepping; afterwards a plain
move still reaches its width."""
import collections
import math
import os
import sys
import unittest

import actionlib
import rospkg
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import GripperCommandAction, GripperCommandActionResult, GripperCommandGoal
from franka_gripper.msg import (GraspAction, GraspActionResult, GraspGoal, MoveAction, MoveActionResult,
                                MoveGoal, StopAction, StopGoal)
from gazebo_msgs.srv import GetWorldProperties
from sensor_msgs.msg import JointState
from std_srvs.srv import Empty

from modrob_sim import waits

sys.path.insert(0, os.path.join(rospkg.RosPack().get_path("modrob_sim"), "test", "fixtures"))
import fuzz_models as F  # noqa: E402

NS = "/franka_gripper"
#: the actions' own refusals of a goal (franka_gazebo's words), made before the command is given
UP_FRONT = ("Only positive speeds allowed", "Target width has to lie", "Can only grasp inside finger width",
            "Commanding out of range position")
DONE = (GoalStatus.PREEMPTED, GoalStatus.SUCCEEDED, GoalStatus.ABORTED, GoalStatus.REJECTED,
        GoalStatus.RECALLED)


def finite(values):
    return all(math.isfinite(v) for v in values)


class GripperFuzz(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        waits.wait_running("", ["franka_gripper"], 60.0)
        cls.results = {}
        cls.clients = {}
        for name, action, result in (("move", MoveAction, MoveActionResult),
                                     ("grasp", GraspAction, GraspActionResult),
                                     ("gripper_action", GripperCommandAction, GripperCommandActionResult)):
            cls.clients[name] = actionlib.ActionClient(NS + "/" + name, action)
            rospy.Subscriber(NS + "/%s/result" % name, result, cls._result, callback_args=name,
                             queue_size=None)
            waits.wait_until(lambda: cls.clients[name].wait_for_server(rospy.Duration(0.05)), 30.0,
                             "the %s action server" % name)
        cls.stop = actionlib.SimpleActionClient(NS + "/stop", StopAction)
        assert waits.wait_for_action_servers(((cls.stop, "stop"),), 30.0) is None
        cls.states = []
        rospy.Subscriber(NS + "/joint_states", JointState,
                         lambda m: cls.states.append(finite(list(m.position) + list(m.velocity))),
                         queue_size=100)
        for srv in ("reset_simulation", "reset_world"):
            rospy.wait_for_service("/gazebo/" + srv, 30.0)
        cls.reset = {srv: rospy.ServiceProxy("/gazebo/" + srv, Empty)
                     for srv in ("reset_simulation", "reset_world")}
        cls.world = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)

    @classmethod
    def _result(cls, msg, name):
        res = msg.result
        ok = res.reached_goal if name == "gripper_action" else res.success
        text = msg.status.text if name == "gripper_action" else res.error
        cls.results[msg.status.goal_id.id] = (msg.status.status, ok, text)

    def sim_time(self):
        return self.world().sim_time

    def goal(self, fz):
        """A goal to one of the three actions, its numbers drawn by ``fz``: (action, goal, the names
        of its values that are not finite)."""
        kind = fz.rng.choice(["move", "grasp", "gripper_action"])
        if kind == "move":
            g = MoveGoal(width=fz.num(0.0, 0.08), speed=fz.num(0.01, 0.2))
            values = {"width": g.width, "speed": g.speed}
        elif kind == "grasp":
            g = GraspGoal(width=fz.num(0.0, 0.079), speed=fz.num(0.01, 0.2), force=fz.num(1.0, 40.0))
            g.epsilon.inner, g.epsilon.outer = fz.num(0.001, 0.01), fz.num(0.001, 0.01)
            values = {"width": g.width, "speed": g.speed, "force": g.force,
                      "epsilon.inner": g.epsilon.inner, "epsilon.outer": g.epsilon.outer}
        else:
            g = GripperCommandGoal()
            g.command.position, g.command.max_effort = fz.num(0.0, 0.04), fz.num(0.0, 40.0)
            values = {"position": g.command.position, "force": g.command.max_effort}
        return kind, g, [k for k, v in values.items() if not math.isfinite(v)]

    def test_1_goals_sent_after_reset_simulation_are_taken(self):
        """reset_simulation sends the clock back: the goals a client sends after it are stamped before
        the goals (and a cancel request) it sent before it; the gripper takes them all the same
        (actionlib's servers order goals by stamp: they had refused every goal until the clock
        passed the old stamps, as 'canceled because another goal was received')."""
        move = actionlib.SimpleActionClient(NS + "/move", MoveAction)
        self.assertIsNone(waits.wait_for_action_servers(((move, "move"),), 30.0))
        waits.wait_until(lambda: rospy.get_time() > 1.0, 30.0, "1 s of simulated time")
        for width in (0.06, 0.03):
            move.send_goal(MoveGoal(width=width, speed=0.1))
            self.assertTrue(waits.wait_for_result(move, 30.0), "no result of the move to %g" % width)
            self.assertEqual(move.get_state(), GoalStatus.SUCCEEDED, move.get_goal_status_text())
            self.assertTrue(move.get_result().success, move.get_result().error)
            if width == 0.06:   # cancel every goal stamped until now, then reset the simulation
                before = rospy.get_time()
                move.cancel_goals_at_and_before_time(rospy.Time.from_sec(before))
                self.reset["reset_simulation"]()
                # (a goal stamped 0 is not ordered: the next one is stamped after 0 and before `before`)
                waits.wait_until(lambda: 0.05 < rospy.get_time() < before, 30.0, "the clock to go back")

    def test_2_hostile_goals_among_stops_cancels_and_resets(self):
        fz = F.Fuzz(25, p_hostile=0.25)
        sent = []           # (goal id, action, handle, names of the values that are not finite)
        plan = []
        for _ in range(2 * F.scale()):      # every kind in each round, in a seeded order
            rnd = ["goal"] * 6 + ["cancel", "stop", "reset_simulation", "reset_world"]
            fz.rng.shuffle(rnd)
            plan += rnd
        for kind in plan:
            if kind == "goal":          # a new goal of the same action preempts the one in progress
                action, g, bad = self.goal(fz)
                gh = self.clients[action].send_goal(g)
                sent.append((gh.comm_state_machine.action_goal.goal_id.id, action, gh, bad))
            elif kind == "cancel" and sent:
                sent[-1][2].cancel()
            elif kind == "stop":
                self.stop.send_goal(StopGoal())
            elif kind in self.reset:
                self.reset[kind]()
            t0 = self.sim_time()
            wait = fz.rng.choice([0.0, 0.01, 0.05, 0.3])
            waits.wait_until(lambda: self.sim_time() >= t0 + wait, 20.0, "/gazebo's clock to go on")
        self.stop.send_goal(StopGoal())
        for _, _, gh, _ in sent:
            gh.cancel()
        for k, (gid, action, gh, bad) in enumerate(sent):
            waits.wait_until(lambda: gid in self.results, 30.0, "the result of goal %d (%s)" % (k, action))
            status, ok, text = self.results[gid]
            self.assertIn(status, DONE)
            if bad:     # never taken: refused up front (naming the value, unless another check of the
                # action's refused the goal first), or recalled (cancelled before the server took it)
                self.assertIn(status, (GoalStatus.ABORTED, GoalStatus.RECALLED),
                              "goal %d (%s) with %s: %s" % (k, action, bad, text))
                if status == GoalStatus.ABORTED:
                    self.assertTrue(any(b in text for b in bad) or text.startswith(UP_FRONT), (bad, text))
        self.assertTrue(any(s[3] for s in sent) and any(not s[3] for s in sent), "both kinds of goal")
        # the gripper still moves where it is told
        gh = self.clients["move"].send_goal(MoveGoal(width=0.05, speed=0.1))
        gid = gh.comm_state_machine.action_goal.goal_id.id
        waits.wait_until(lambda: gid in self.results, 30.0, "the last move's result")
        self.assertEqual(self.results[gid][:2], (GoalStatus.SUCCEEDED, True), self.results[gid])
        self.assertTrue(self.states and all(self.states), "no or non-finite gripper joint states")
        rospy.loginfo("gripper_fuzz: %d goals (%d with a NaN/inf value): %s" % (
            len(sent), sum(1 for s in sent if s[3]),
            dict(collections.Counter((s, ok) for s, ok, _ in self.results.values()))))


if __name__ == "__main__":
    rospy.init_node("gripper_fuzz")
    rostest.rosrun("franka_sim", "gripper_fuzz", GripperFuzz)
