"""Katana kinematics (pure): FK against katana_description's frames, the seed's quadrant rule, and
FK(IK(p)) = p within 1 mm over a grid of the reachable workspace for the triangle and grasp IK."""
import math

import numpy as np
import pytest

from katana_sim import kinematics as k
from katana_sim.errors import UnreachableError


def test_zero_pose_matches_katana_description_lengths():
    t = k.fk([0, 0, 0, 0, 0])
    # all links along x, the 6M90A gripper (LINK5) standing up at 90 degrees
    assert t[:3, 3] == pytest.approx([k.LINK2 + k.LINK3 + k.LINK4, 0, k.BASE_HEIGHT + k.LINK5], abs=1e-12)
    assert t[:3, 2] == pytest.approx([0, 0, 1], abs=1e-12)   # approach axis up


def test_lift_joints_raise_the_arm_and_pan_turns_left():
    assert k.tool_position([0, 0.2, 0, 0, 0])[2] > k.tool_position([0, 0, 0, 0, 0])[2]
    assert k.tool_position([0.3, 0, 0, 0, 0])[1] > 0


@pytest.mark.parametrize("x, y", [(0.3, 0.2), (-0.3, 0.2), (-0.3, -0.2), (0.3, -0.2), (0.0, 0.4), (0.4, 0.0),
                                  (-0.4, 0.0), (0.0, -0.4)])
def test_seed_quadrant_rule_gives_the_pan_angle_in_every_quadrant(x, y):
    q1 = k.pan_angle(x, y)
    assert math.cos(q1) == pytest.approx(x / math.hypot(x, y))
    assert math.sin(q1) == pytest.approx(y / math.hypot(x, y))


def test_seed_base_angle_as_written():
    assert k.seed_base_angle(1.0, 1.0) == pytest.approx(math.pi / 4)            # y > 0
    assert k.seed_base_angle(-1.0, -1.0) == pytest.approx(math.pi / 4 - math.pi)  # y < 0, x < 0
    assert k.seed_base_angle(1.0, -1.0) == pytest.approx(-math.pi / 4 + math.pi)  # y < 0, x >= 0


def grid():
    for r in np.arange(0.2, 0.56, 0.03):
        for z in np.arange(-0.05, 0.45, 0.03):
            for a in (-2.5, -1.0, 0.0, 0.7, 2.0):
                yield (r * math.cos(a), r * math.sin(a), z)


@pytest.mark.parametrize("solver", [k.triangle_ik, k.grasp_ik])
def test_fk_of_ik_is_the_target_within_1mm_over_the_workspace(solver):
    solved = 0
    for p in grid():
        try:
            q = solver(p)
        except UnreachableError:
            continue
        assert k.within_limits(q)
        assert np.linalg.norm(k.tool_position(q) - p) < 1e-3, (p, q)
        solved += 1
    assert solved > 150   # the grid really covers reachable targets


def test_grasp_ik_points_the_gripper_horizontally_away_from_the_base_with_vertical_hinges():
    q = k.grasp_ik((0.3, 0.15, 0.06))
    frames = k.link_frames(q)
    approach = frames[-1][:3, 2]
    assert approach == pytest.approx(np.array([0.3, 0.15, 0]) / math.hypot(0.3, 0.15), abs=1e-9)
    assert abs(frames[4][2, 2]) == pytest.approx(1.0)   # wrist roll axis (finger hinges) vertical


@pytest.mark.parametrize("target, words", [
    ((1.0, 0.0, 0.2), "reaches"),
    ((0.0, 0.0, 0.5), "pan axis"),
    ((float("nan"), 0, 0), "finite"),
    ((0.05, 0.0, 0.55), "joint limits"),
])
def test_unreachable_targets_are_refused_with_the_reason(target, words):
    with pytest.raises(UnreachableError, match=words):
        k.triangle_ik(target)


def test_grasp_ik_refuses_a_target_beyond_reach():
    with pytest.raises(UnreachableError, match="more than the arm"):
        k.grasp_ik((0.8, 0.0, 0.06))
