"""Grasp-pose inverse kinematics for the side grasp of a lying light bulb.

The gripper (modrob_description/urdf/gripper.xacro) closes its fingers along its y axis; each
finger's flat 50 mm pad presses on the glass cylinder along a line.
For a grasp that cannot wedge the bulb up or down, the closing direction must be horizontal and
across the bulb: y_g parallel to axis x z (either sign). The gripper may then turn about y_g:
its x axis may tilt from the bulb axis by up to ``max_tilt`` (the pads still touch the
cylinder along a line), and its approach direction (z) must point down by at least ``min_down``.

So a grasp fixes the grasp centre (3 numbers) and the closing direction (2), leaving one degree of
freedom to a 6-joint arm; for the 3-joint arms of the two-robot layout the layout puts every bulb
in line with the arm so that an exact solution exists. Solved by bounded least squares (scipy)
on KDL forward kinematics (modrob_kinematics.kdl_urdf) from seeded starts. Pure: no rospy.
"""
import math
import random

import numpy as np
from scipy.optimize import least_squares

from modrob_msgs.errors import ModrobError


class GraspIkError(ModrobError):
    """No joint configuration puts the gripper at the requested grasp."""


def _rot(frame):
    m = frame.M
    return np.array([[m[i, j] for j in range(3)] for i in range(3)])


def closing_direction(axis):
    """Horizontal unit vector across a bulb whose axis is ``axis``."""
    y = np.cross(np.asarray(axis, dtype=float), [0.0, 0.0, 1.0])
    n = np.linalg.norm(y)
    if n < 1e-6:
        raise GraspIkError("a bulb standing upright (axis %r) cannot be grasped from the side"
                           % (tuple(axis),))
    return y / n


class GraspIk(object):
    """chain: a modrob_kinematics.kdl_urdf.KinematicChain from the world to the grasp-centre link
    (``<prefix>gripper_tcp``)."""

    def __init__(self, chain, pos_tol=0.002, closing_tol_deg=4.0, max_tilt_deg=35.0,
                 min_down=math.radians(30.0), seed=0):
        self.chain = chain
        self.n = chain.n_joints
        self.lower = np.array([max(lo, -math.pi) for lo in chain.lower])
        self.upper = np.array([min(hi, math.pi) for hi in chain.upper])
        self.pos_tol = pos_tol
        self.closing_tol = math.radians(closing_tol_deg)
        self.max_tilt = math.radians(max_tilt_deg)
        self.min_down = min_down
        self.rng = random.Random(seed)

    def tool(self, q):
        f = self.chain.fk(list(q))
        return np.array([f.p[0], f.p[1], f.p[2]]), _rot(f)

    def _residual(self, q, target, axis, ydir, approach, approach_w):
        p, r = self.tool(q)
        res = list(p - target)
        res += list(0.5 * np.cross(r[:, 1], ydir))
        tilt = math.acos(min(1.0, abs(float(np.dot(r[:, 0], axis)))))
        res.append(0.5 * max(0.0, tilt - self.max_tilt))
        res.append(2.0 * max(0.0, r[2, 2] + math.sin(self.min_down)))
        if approach is not None:
            res += list(approach_w * (r[:, 2] - approach))
        return np.array(res)

    def errors(self, q, target, axis):
        """(position error m, closing-direction error rad, tilt rad, approach z component)."""
        p, r = self.tool(q)
        ydir = closing_direction(axis)
        close = math.acos(min(1.0, abs(float(np.dot(r[:, 1], ydir)))))
        tilt = math.acos(min(1.0, abs(float(np.dot(r[:, 0], axis)))))
        return float(np.linalg.norm(p - target)), close, tilt, float(r[2, 2])

    def ok(self, q, target, axis):
        pe, ce, tilt, az = self.errors(q, target, axis)
        return (pe <= self.pos_tol and ce <= self.closing_tol and tilt <= self.max_tilt + 0.02
                and az <= -math.sin(self.min_down) + 0.02)

    def solve(self, target, axis, q0=None, approach=None, attempts=12, approach_weight=0.05):
        """Joint vector for the grasp centre at ``target`` closing across a bulb along ``axis``.
        approach: optional preferred approach direction (weighed lightly). Raises GraspIkError."""
        target = np.asarray(target, dtype=float)
        axis = np.asarray(axis, dtype=float)
        axis = axis / np.linalg.norm(axis)
        ydir = closing_direction(axis)
        if approach is not None:
            approach = np.asarray(approach, dtype=float)
            approach = approach / np.linalg.norm(approach)
        starts = []
        if q0 is not None:
            starts.append(np.clip(np.asarray(q0, dtype=float), self.lower, self.upper))
        while len(starts) < attempts:
            starts.append(np.array([self.rng.uniform(lo, hi) for lo, hi in zip(self.lower, self.upper)]))
        best = None
        for k, s in enumerate(starts):
            sol = least_squares(self._residual, s, bounds=(self.lower, self.upper),
                                args=(target, axis, ydir, approach,
                                      approach_weight if approach is not None else 0.0),
                                xtol=1e-10, ftol=1e-10, max_nfev=400)
            if approach is not None and not self.ok(sol.x, target, axis):
                # the preference pulled it off the target: polish without it
                sol = least_squares(self._residual, sol.x, bounds=(self.lower, self.upper),
                                    args=(target, axis, ydir, None, 0.0), xtol=1e-10, ftol=1e-10,
                                    max_nfev=200)
            good = self.ok(sol.x, target, axis)
            pe = self.errors(sol.x, target, axis)[0]
            score = pe + (0.0 if good else 1.0)
            if q0 is not None:
                score += 0.01 * float(np.max(np.abs(sol.x - starts[0])))
            if best is None or score < best[0]:
                best = (score, sol.x, good)
            if good and q0 is not None and k == 0:
                break
        if not best[2]:
            pe, ce, tilt, az = self.errors(best[1], target, axis)
            raise GraspIkError("no grasp of (%.3f, %.3f, %.3f) across a bulb along (%.2f, %.2f, %.2f): best "
                               "position error %.4f m, closing direction off by %.1f deg, tilt %.1f deg, "
                               "approach z %.2f" % (tuple(target) + tuple(axis) + (pe, math.degrees(ce),
                                                                                   math.degrees(tilt), az)))
        return [float(v) for v in best[1]]
