#!/usr/bin/env python3
"""Close the gripper on the bulb at the red tip, lift it clear of the slides, then shake the arm: for
each phase of ``~phases`` (a list of {joints: [...], amplitude: rad}; default one phase of ``~joints``
at ``~amplitude``) the phase's joints swing sinusoidally at ``~freq`` Hz for ``~seconds`` s (after a
fade-in of ``~fade`` s), one phase after the other, without opening the gripper.

Checks: the bulb stays in the gripper (its glass centre within ``~max_offset`` = 30 mm of the grasp
centre; ``~must_hold``), the fingers press with the grip force, /gazebo reports no blow-up, and the arm
really swung: each shaken joint's measured swing is at least ``~min_swing_share`` of the commanded
amplitude (so a sluggish arm cannot pass the test by not shaking).

How it measures (docs/bulbs_and_slides.md, grasp robustness):
* The bulb's offset is taken from ONE /gazebo/link_states message (the bulb's link and the
  gripper's TCP link of the same simulation step), in the gripper frame. Comparing the bulb's pose
  from /gazebo/model_states with the forward kinematics of /joint_states (50 Hz) mixes two
  instants: while joint1 swings the TCP moves at up to 0.9 m/s, so 60 ms between them made a bulb
  sitting 0.9 mm from the grasp centre look 54 mm away (a "drop" that never happened).
* The swing stays inside the joint range: a phase first moves each of its joints smoothly (1 s,
  cosine) to a centre at least ``~limit_reach`` * amplitude + 0.05 rad inside the joint limits. The
  joint controllers overshoot a 1.5 Hz sinusoid by up to 1.5x (joint5), and a joint that runs into its
  mechanical stop stops within a few ms: the jolt throws the fingers open (what a swing of joint5 from
  the grasp pose, 0.13 rad from its stop, did).
"""
import math
import sys
import threading
import unittest

import numpy as np
import rospy
import rostest
from gazebo_msgs.msg import LinkStates, ODEPhysics
from gazebo_msgs.srv import GetPhysicsProperties, SetPhysicsProperties
from std_msgs.msg import String

from modrob_motion.bulbs_and_slides.layout import Layout, bulb_grasp_point
from modrob_motion.bulbs_and_slides.ros_robot import StreamClock, sim_sleep
from modrob_motion.bulbs_and_slides.scenario import Scenario
from modrob_motion.cartesian import default_tip
from modrob_sim import waits
from modrob_sim.physics.transforms import quat_conj, quat_rotate

RATE = 100.0          # Hz of set-points, as the scenario streams them
LIMIT_MARGIN = 0.05   # rad kept free beyond the expected swing


class BulbInGripper(object):
    """The bulb's glass centre relative to the gripper's grasp centre, in the gripper frame, from
    single /gazebo/link_states messages. ``worst`` is the largest distance while armed."""

    def __init__(self, layout, bulb_link, tcp_link):
        self.layout = layout
        self.bulb_link = bulb_link
        self.tcp_link = tcp_link
        self._lock = threading.Lock()
        self.latest = None
        self.worst = 0.0
        self.armed = False
        self.samples = 0
        self.sub = rospy.Subscriber("/gazebo/link_states", LinkStates, self._on_links, queue_size=5)

    def _on_links(self, msg):
        try:
            i = msg.name.index(self.bulb_link)
            k = msg.name.index(self.tcp_link)
        except ValueError:
            return
        b, g = msg.pose[i], msg.pose[k]
        bulb = ((b.position.x, b.position.y, b.position.z),
                (b.orientation.x, b.orientation.y, b.orientation.z, b.orientation.w))
        centre, _ = bulb_grasp_point(self.layout, bulb)
        gq = (g.orientation.x, g.orientation.y, g.orientation.z, g.orientation.w)
        off = np.array(quat_rotate(quat_conj(gq), tuple(centre - np.array([g.position.x, g.position.y,
                                                                           g.position.z]))))
        with self._lock:
            self.latest = off
            if self.armed:
                self.samples += 1
                self.worst = max(self.worst, float(np.linalg.norm(off)))

    def arm(self, on=True):
        with self._lock:
            self.armed = on

    def wait(self, timeout=30.0):
        """Until the first message came, up to ``timeout`` wall seconds (the subscription's
        connection takes wall time; 30 s of simulated time are ~1 wall s at real_time_factor 0)."""
        return waits.wait_until(lambda: self.latest is not None, timeout)


def centre_inside_limits(q, lower, upper, reach):
    """q moved just far enough that q +- reach stays inside [lower, upper]; None if it cannot."""
    lo, hi = lower + reach, upper - reach
    if lo > hi:
        return None
    return min(max(q, lo), hi)


class GraspSanity(unittest.TestCase):
    def move_smoothly(self, r, names, start, goal, duration):
        clock = StreamClock(2.0 / RATE)
        while not rospy.is_shutdown():
            s = min(1.0, clock.tick() / duration)
            r.arm.command(names, start + (0.5 - 0.5 * math.cos(math.pi * s)) * (goal - start))
            if s >= 1.0:
                return
            sim_sleep(1.0 / RATE)

    def set_pace(self, real_time_factor):
        """The simulator's pace through Gazebo's service: max_update_rate = factor / time_step."""
        rospy.wait_for_service("/gazebo/set_physics_properties", 30)
        now = rospy.ServiceProxy("/gazebo/get_physics_properties", GetPhysicsProperties)()
        res = rospy.ServiceProxy("/gazebo/set_physics_properties", SetPhysicsProperties)(
            time_step=now.time_step, max_update_rate=real_time_factor / now.time_step, gravity=now.gravity,
            ode_config=ODEPhysics())       # all zero: the solver's settings stay as they are
        self.assertTrue(res.success, res.status_message)

    def shake(self, sc, r, joints, amplitude, freq, seconds, fade, reach_factor, monitor):
        """One phase; returns ({joint: measured swing}, [finger efforts])."""
        names = list(r.info.arm_joints)
        idx = [names.index(j) for j in joints]
        # from the last set-points, not the measured joints: their difference (the joints'
        # steady-state error) would be a set-point step, a jolt
        q0 = np.array([r.arm.cmd.get(n, m) for n, m in zip(names, r.arm.measured(names))])
        centre = q0.copy()
        for i in idx:
            c = centre_inside_limits(q0[i], r.chain.lower[i], r.chain.upper[i],
                                     reach_factor * amplitude + LIMIT_MARGIN)
            self.assertIsNotNone(c, "%s cannot swing %.2f rad inside its limits [%.3f, %.3f]"
                                 % (names[i], amplitude, r.chain.lower[i], r.chain.upper[i]))
            centre[i] = c
        if np.max(np.abs(centre - q0)) > 1e-6:
            sc.log("  moving %s to %s rad, so that the swing stays inside the joint limits"
                   % (", ".join(names[i] for i in idx), ", ".join("%.3f" % centre[i] for i in idx)))
            self.move_smoothly(r, names, q0, centre, 1.0)
            sim_sleep(0.3)
        monitor.arm(True)
        fingers = r.info.gripper.joints
        seen, efforts = [], []
        clock = StreamClock(2.0 / RATE)
        t0 = rospy.get_time()
        while not rospy.is_shutdown():
            t = clock.tick()
            if t > seconds + fade:
                break
            q = centre.copy()
            envelope = min(1.0, t / fade) if fade > 0 else 1.0
            for i in idx:
                q[i] += envelope * amplitude * math.sin(2 * math.pi * freq * t)
            r.arm.command(names, q)
            if t > fade:
                seen.append(r.arm.measured(names)[idx])
            efforts.append(float(np.mean(np.abs(r.arm.efforts(fingers)))))
            sim_sleep(1.0 / RATE)
        # back to the centre (the sinusoid ends near it), so the next phase starts from rest
        r.arm.command(names, centre)
        sim_sleep(0.3)
        monitor.arm(False)
        swing = {}
        if seen:
            seen = np.array(seen)
            swing = {j: 0.5 * float(np.ptp(seen[:, k])) for k, j in enumerate(joints)}
        sc.log("  shaken %s for %.1f s at %.2f Hz, %.2f rad (%.1f s of simulated time, %d late set-points "
               "held back): measured swing %s rad; bulb at most %.1f mm from the grasp centre so far (%d "
               "link_states samples)"
               % ("+".join(joints), seconds, freq, amplitude, rospy.get_time() - t0, clock.capped,
                  ", ".join("%s %.3f" % kv for kv in swing.items()), 1000 * monitor.worst, monitor.samples))
        return swing, efforts

    def test_shaking_does_not_drop_the_bulb(self):
        rospy.init_node("bas_grasp_check")
        force = float(rospy.get_param("~grip_force", 3.0))
        freq = float(rospy.get_param("~freq", 1.5))
        seconds = float(rospy.get_param("~seconds", 5.0))
        fade = float(rospy.get_param("~fade", 0.3))
        max_offset = float(rospy.get_param("~max_offset", 0.03))
        reach_factor = float(rospy.get_param("~limit_reach", 1.5))
        phases = rospy.get_param("~phases", None)
        if not phases:
            phases = [{"joints": rospy.get_param("~joints", ["joint4", "joint6"]),
                       "amplitude": float(rospy.get_param("~amplitude", 0.25))}]
        events = []
        rospy.Subscriber("/gazebo/guard_events", String, lambda m: events.append(m.data))
        layout = Layout.load("one_robot")
        sc = Scenario(layout, log=rospy.loginfo)
        sc.world.wait()
        bulb = sc.tip_bulb()          # the bulb the scenario's grasp picks
        # the scenario's own grasp: open, pick the tip bulb, lift, raise 0.12 m clear of the slides;
        # the phases below shake, measured as described above
        sc.grasp_and_lift()
        r = sc.robots[0]
        tip = default_tip(rospy.get_param("/modrob0/robot_description"), r.info.gripper.joints)
        monitor = BulbInGripper(layout, "%s::link" % bulb, "modrob0::%s" % tip)
        self.assertTrue(monitor.wait(), "no /gazebo/link_states with %s and modrob0::%s" % (bulb, tip))
        sc.log("  after the lift: bulb %.1f mm from the grasp centre (gripper frame %s mm)"
               % (1000 * np.linalg.norm(monitor.latest), np.round(1000 * monitor.latest, 1)))
        # the shake is a 100 Hz set-point stream from this node, through motion_publisher, as the
        # scenario drives the arm: at real_time_factor 0 a loaded machine starves that chain while
        # the simulator runs on (every set-point late, a swing of 0.04 of the 0.2 rad streamed).
        # The grasp and the lift above ran as fast as possible; the shake runs at real time.
        self.set_pace(1.0)
        efforts = []
        share = float(rospy.get_param("~min_swing_share", 0.7))
        sluggish = []     # reported after all phases, so that one sluggish joint does not hide the others
        for ph in phases:
            joints = list(ph["joints"])
            amplitude = float(ph["amplitude"])
            swing, eff = self.shake(sc, r, joints, amplitude, freq, seconds, fade, reach_factor, monitor)
            efforts += eff
            if rospy.get_param("~must_hold", True):
                self.assertLess(monitor.worst, max_offset,
                                "the bulb left the gripper while shaking %s (%.1f mm from the grasp centre)"
                                % ("+".join(joints), 1000 * monitor.worst))
            for j in joints:
                got = swing.get(j, 0.0)
                if not got > share * amplitude:
                    sluggish.append("%s swung only %.3f rad of the commanded %.2f" % (j, got, amplitude))
        self.assertEqual(sluggish, [], "; ".join(sluggish))
        self.assertGreater(monitor.samples, 0, "no /gazebo/link_states while shaking")
        pose = sc.world.pose(bulb)
        self.assertTrue(pose is not None and 0.9 < pose[0][2] < 2.0 and abs(pose[0][0]) < 1.1
                        and abs(pose[0][1]) < 0.7, "%s left the table: %r" % (bulb, pose))
        effort = float(np.mean(efforts)) if efforts else float("nan")
        self.assertAlmostEqual(effort, force, delta=0.15 * force,
                               msg="fingers press with %.2f N, the grip force is %.1f N" % (effort, force))
        self.assertEqual(events, [], "the simulator reported blow-ups: %s" % events)


if __name__ == "__main__":
    rostest.rosrun("modrob_motion", "bas_grasp", GraspSanity, sys.argv)
