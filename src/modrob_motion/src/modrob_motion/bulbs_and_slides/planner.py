"""Joint-space plans for the pick and the place, from Cartesian waypoints solved with GraspIk.

Every Cartesian segment is cut into short steps, each solved with the previous solution as the
seed, so consecutive configurations stay close (no flips of the redundant arm mid-way)."""
import math

import numpy as np

from modrob_motion.bulbs_and_slides import ScenarioError
from modrob_motion.bulbs_and_slides.grasp_ik import GraspIkError

MAX_STEP_JUMP = 0.35   # rad: larger jumps between neighbouring path points mean the IK flipped


class Segment(object):
    """A named list of configurations, with the speed to run them at and what the gripper does
    after it (None, 'open', 'close')."""

    def __init__(self, name, configs, speed, gripper_after=None, settle=True):
        self.name = name
        self.configs = [np.asarray(c, dtype=float) for c in configs]
        self.speed = speed
        self.gripper_after = gripper_after
        self.settle = settle

    def __repr__(self):
        return "Segment(%s, %d points, %.2f rad/s, then %s)" % (
            self.name, len(self.configs), self.speed, self.gripper_after)


class ArmPlanner(object):
    """ik: GraspIk for the arm (world frame -> gripper_tcp)."""

    def __init__(self, ik, step=0.02):
        self.ik = ik
        self.step = step

    def solve(self, point, axis, seed, approach=None, attempts=10):
        try:
            return np.array(self.ik.solve(point, axis, q0=seed, approach=approach, attempts=attempts))
        except GraspIkError as exc:
            raise ScenarioError(str(exc))

    def line(self, q_from, p_from, p_to, axis, approach=None):
        """Configurations along the straight line p_from -> p_to (excluding p_from)."""
        p_from, p_to = np.asarray(p_from, dtype=float), np.asarray(p_to, dtype=float)
        n = max(1, int(math.ceil(np.linalg.norm(p_to - p_from) / self.step)))
        out = []
        q = np.asarray(q_from, dtype=float)
        for k in range(1, n + 1):
            p = p_from + (p_to - p_from) * (k / float(n))
            try:
                qn = np.array(self.ik.solve(p, axis, q0=q, approach=approach, attempts=1))
            except GraspIkError:
                qn = self.solve(p, axis, q, approach, attempts=10)
            if np.max(np.abs(qn - q)) > MAX_STEP_JUMP:
                raise ScenarioError("the arm would flip between (%.3f, %.3f, %.3f) and the next point on the "
                                    "way to (%.3f, %.3f, %.3f)" % (tuple(p_from) + tuple(p_to)))
            out.append(qn)
            q = qn
        return out

    def tool(self, q):
        return self.ik.tool(q)


def plan_pick_and_place(planner, q_start, grasp_pt, pick_axis, place_pt, place_axis, lift=0.12, pre=0.07,
                        fast=0.5, slow=0.15):
    """Segments for: approach above the bulb -> descend along the tool axis -> close -> lift ->
    carry at lift height -> lower over the release point -> open -> retreat up."""
    grasp_pt = np.asarray(grasp_pt, dtype=float)
    place_pt = np.asarray(place_pt, dtype=float)
    up = np.array([0.0, 0.0, 1.0])
    q_grasp = planner.solve(grasp_pt, pick_axis, q_start, approach=(0, 0, -1), attempts=16)
    _, r = planner.tool(q_grasp)
    a = r[:, 2]
    pre_pt = grasp_pt - pre * a
    q_pre = planner.solve(pre_pt, pick_axis, q_grasp, approach=a)
    segs = [Segment("to pre-grasp", [q_start, q_pre], fast, gripper_after=None)]
    descend = planner.line(q_pre, pre_pt, grasp_pt, pick_axis, approach=a)
    segs.append(Segment("descend to the bulb", [q_pre] + descend, slow, gripper_after="close"))
    q = descend[-1]
    lift_pt = grasp_pt + lift * up
    lifted = planner.line(q, grasp_pt, lift_pt, pick_axis, approach=a)
    segs.append(Segment("lift", [q] + lifted, slow))
    q = lifted[-1]
    above_place = place_pt + lift * up
    carry = planner.line(q, lift_pt, above_place, place_axis)
    segs.append(Segment("carry over the blue slide", [q] + carry, fast * 0.6))
    q = carry[-1]
    lower = planner.line(q, above_place, place_pt, place_axis)
    segs.append(Segment("lower", [q] + lower, slow, gripper_after="open"))
    q = lower[-1]
    retreat = planner.line(q, place_pt, above_place, place_axis)
    segs.append(Segment("retreat", [q] + retreat, slow, settle=False))
    return segs
