"""IK on the Bulbs and Slides 6-DoF arm must find configurations inside the joint limits.

Fixture: ``rosrun modrob_build modrob_urdf --order 59,3,55,63,64,4,66,4,67,5,56,5 --gripper``
(committed, so this package's tests do not depend on modrob_build). Targets are the tool
positions of random in-limit configurations: each is reachable within the limits by construction,
so 'unreachable' would be a wrong answer."""
import os
import random

import pytest

from modrob_kinematics import kdl_urdf

FIXTURE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures",
                       "modrob_6dof_gripper.urdf")


@pytest.fixture(scope="module")
def arm():
    with open(FIXTURE) as f:
        return kdl_urdf.KinematicChain.from_urdf_string(f.read(), "world", "modrob0_gripper_tcp")


def test_position_targets_of_in_limit_configurations_are_solved_within_limits(arm):
    rng = random.Random(7)
    home = [0.0] * arm.n_joints
    failures = []
    for k in range(25):
        q_true = [rng.uniform(lo, hi) for lo, hi in zip(arm.lower[:6], arm.upper[:6])]
        target = arm.fk_position(q_true)
        try:
            q = arm.ik(target, q0=home, attempts=4, seed=k)
        except kdl_urdf.UnreachableError as exc:
            failures.append("%d: %s" % (k, exc))
            continue
        assert arm.within_limits(q)
        err = sum((a - b) ** 2 for a, b in zip(arm.fk_position(q), target)) ** 0.5
        assert err < 1e-4
    assert not failures, "\n".join(failures)


def test_full_pose_target_within_limits(arm):
    rng = random.Random(3)
    for k in range(10):
        q_true = [rng.uniform(0.8 * lo, 0.8 * hi) for lo, hi in zip(arm.lower, arm.upper)]
        target = arm.fk(q_true)
        q = arm.ik(target, q0=[0.0] * arm.n_joints, attempts=6, seed=k)
        assert arm.within_limits(q)
        pos_err, rot_err = arm._error(q, target, False)
        assert pos_err < 1e-4 and rot_err < 1e-3
