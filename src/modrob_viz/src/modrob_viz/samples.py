"""Sample joint motions for demos and tests (no rospy): a smooth multi-joint trajectory like the
TP team's planner output (the seed's 3700 points) and a joint-space wave to move a robot."""
import math

import numpy as np

from modrob_viz.errors import TrajectoryError
from modrob_viz.joint_path import JointPath


def _range(limits):
    lo, hi = limits
    lo = -math.pi if math.isinf(lo) else lo
    hi = math.pi if math.isinf(hi) else hi
    return 0.5 * (lo + hi), 0.5 * (hi - lo)


def sample_joint_trajectory(names, limits, n=3700, duration=11.1, amplitude=0.6):
    """A smooth trajectory of ``n`` points over ``duration`` s: each joint swings about the middle
    of its range by ``amplitude`` of its half range (at most 1.2 rad) with its own frequency."""
    if n < 2:
        raise TrajectoryError("a sample trajectory needs n >= 2 points, got %r" % (n,))
    if not 0 < amplitude <= 1:
        raise TrajectoryError("amplitude must be in (0, 1], got %r" % (amplitude,))
    s = np.linspace(0.0, 1.0, int(n))
    cols = []
    for j, name in enumerate(names):
        mid, half = _range(limits[name])
        a = min(1.2, amplitude * half)
        if j == 0:
            cols.append(mid + a * np.sin(math.pi * (s - 0.5)))           # one sweep across
        else:  # bent by a decreasing offset, waving j times over the trajectory
            offset = a * max(0.2, 0.7 - 0.2 * (j - 1))
            cols.append(mid + offset + 0.3 * a * np.sin(2 * math.pi * j * s + j))
    return JointPath(names, np.column_stack(cols) if cols else np.zeros((int(n), 0)), s * duration)


def joint_wave(names, limits, t, period=8.0, amplitude=0.5):
    """Joint positions at time ``t`` [s] of a slow wave through every joint (for demos)."""
    out = []
    for j, name in enumerate(names):
        mid, half = _range(limits[name])
        a = min(1.0, amplitude * half)
        out.append(mid + a * math.sin(2 * math.pi * t / period + 0.9 * j))
    return out


def follow_path_ik(chain, points, wobble=0.01, q0=None):
    """Joint configurations that put ``chain``'s tip along ``points`` with a slow sideways
    wobble of ``wobble`` m (an imperfect human operator), each IK started from the previous
    solution; the last one is exactly on the last point. Unreachable points are skipped."""
    from modrob_viz.errors import UnreachableError
    pts = np.asarray(points, dtype=float)
    q = list(q0) if q0 is not None else None
    out = []
    for i, p in enumerate(pts):
        s = i / max(1, len(pts) - 1)
        off = 0.0 if i == len(pts) - 1 else wobble * math.sin(2 * math.pi * 3 * s)
        target = (p[0], p[1] + off, p[2] + 0.5 * off)
        try:
            q = chain.ik(target, q0=q, attempts=5)
        except UnreachableError:
            continue
        out.append(q)
    return out
