"""KDL on the Katana's URDF (the xacro as katana.launch loads it): its FK equals the analytic FK of
katana_sim.kinematics, and its numeric IK gives FK(IK(p)) = p within 1 mm over a workspace grid;
unreachable targets are refused with the reason."""
import math
import os
import random
import subprocess

import numpy as np
import pytest

from katana_sim import kinematics as kin
from katana_sim.errors import UnreachableError
from katana_sim.kinematics_node import KatanaKinematics, _quat_of

XACRO = os.path.join(os.path.dirname(__file__), "..", "..", "urdf", "katana_450_6m90a.urdf.xacro")


@pytest.fixture(scope="module")
def kdl():
    xml = subprocess.check_output(["xacro", XACRO, "fixed:=true", "base_z:=0.75"], text=True)
    return KatanaKinematics(xml)


def test_kdl_fk_equals_the_analytic_fk(kdl):
    rng = random.Random(3)
    for _ in range(200):
        q = [rng.uniform(lo, hi) for lo, hi in zip(kin.LOWER, kin.UPPER)]
        assert np.allclose(kdl.fk(q), kin.fk(q), atol=1e-9), q


def test_kdl_ik_fk_round_trip_within_1mm_over_the_workspace(kdl):
    solved, refused = 0, 0
    for r in np.arange(0.2, 0.51, 0.06):
        for z in np.arange(0.0, 0.46, 0.09):
            for a in (-2.0, -0.5, 0.6, 2.4):
                p = (r * math.cos(a), r * math.sin(a), z)
                try:
                    q = kdl.ik(p, solver="kdl", position_only=True)
                except UnreachableError:
                    refused += 1
                    continue
                assert kin.within_limits(q, margin=-1e-9)
                assert np.linalg.norm(kin.tool_position(q) - p) < 1e-3, (p, q)
                solved += 1
    assert solved >= 100, (solved, refused)


def test_kdl_ik_with_the_grasp_orientation(kdl):
    q_ref = kin.grasp_ik((0.38, 0.12, 0.06))
    m = kin.fk(q_ref)
    q = kdl.ik(m[:3, 3], _quat_of(m[:3, :3]), solver="kdl", position_only=False)
    assert np.allclose(kin.fk(q), m, atol=2e-3)


def test_kdl_refuses_a_target_out_of_reach_with_the_reason(kdl):
    with pytest.raises(UnreachableError, match="reaches at most"):
        kdl.ik((1.5, 0.0, 0.2), solver="kdl")
