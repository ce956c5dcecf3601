"""Tier 1: the two-robot clearance geometry (skeleton segments from a URDF, segment distances)."""
import math

import numpy as np
import pytest

from modrob_sim.bulbs_and_slides import ScenarioError
from modrob_sim.bulbs_and_slides.clearance import (clearance, positions_by_model, segment_distance,
                                                   skeleton, urdf_parents)

URDF = """<robot name="r">
  <link name="base"/><link name="upper"/><link name="tool"/><link name="lumped"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/></joint>
  <joint name="j2" type="fixed"><parent link="upper"/><child link="lumped"/></joint>
  <joint name="j3" type="revolute"><parent link="lumped"/><child link="tool"/></joint>
</robot>"""


def P(*v):
    return np.array(v, dtype=float)


@pytest.mark.parametrize("a,b,want", [
    ((P(0, 0, 0), P(1, 0, 0)), (P(0, 1, 0), P(1, 1, 0)), 1.0),             # parallel
    ((P(0, 0, 0), P(1, 0, 0)), (P(0.5, -1, 1), P(0.5, 1, 1)), 1.0),         # crossing above
    ((P(0, 0, 0), P(1, 0, 0)), (P(2, 0, 0), P(3, 0, 0)), 1.0),              # collinear, apart
    ((P(0, 0, 0), P(1, 0, 0)), (P(-1, 2, 0), P(-1, 2, 0)), math.sqrt(5)),   # point vs segment end
    ((P(0, 0, 0), P(0, 0, 0)), (P(3, 4, 0), P(3, 4, 0)), 5.0),              # two points
    ((P(0, 0, 0), P(2, 2, 0)), (P(0, 2, 0), P(2, 0, 0)), 0.0),              # intersecting
])
def test_segment_distance_cases(a, b, want):
    assert segment_distance(a[0], a[1], b[0], b[1]) == pytest.approx(want, abs=1e-9)
    assert segment_distance(b[0], b[1], a[0], a[1]) == pytest.approx(want, abs=1e-9)


def test_segment_distance_matches_brute_force_sampling():
    rng = np.random.default_rng(3)
    s = np.linspace(0, 1, 201)
    for _ in range(20):
        p1, q1, p2, q2 = (rng.uniform(-1, 1, 3) for _ in range(4))
        a = p1 + s[:, None] * (q1 - p1)
        b = p2 + s[:, None] * (q2 - p2)
        brute = np.min(np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2))
        d = segment_distance(p1, q1, p2, q2)
        assert d <= brute + 1e-9
        assert d == pytest.approx(brute, abs=0.02)


def test_skeleton_skips_links_the_simulator_does_not_report():
    parents = urdf_parents(URDF)
    assert parents == {"upper": "base", "lumped": "upper", "tool": "lumped"}
    segs = skeleton(parents, {"base": (0, 0, 0), "upper": (0, 0, 1), "tool": (1, 0, 1)})
    names = sorted(n for n, _, _ in segs)
    assert names == ["base-upper", "upper-tool"]


def test_clearance_of_two_arms_names_the_closest_pair():
    parents = urdf_parents(URDF)
    arm_a = skeleton(parents, {"base": (0, 0, 0), "upper": (0, 0, 1), "tool": (0.6, 0, 1)})
    arm_b = skeleton(parents, {"base": (1, 0, 0), "upper": (1, 0, 1), "tool": (1, 0.5, 1)})
    d, na, nb = clearance(arm_a, arm_b)
    assert d == pytest.approx(0.4)
    assert (na, nb) == ("upper-tool", "base-upper")


def test_positions_by_model_splits_link_states_names():
    out = positions_by_model(["modrob0::a", "modrob1::b", "table::top", "bare"], [1, 2, 3, 4],
                             ["modrob0", "modrob1"])
    assert out == {"modrob0": {"a": 1}, "modrob1": {"b": 2}}


def test_bad_urdf_is_a_scenario_error_that_says_so():
    with pytest.raises(ScenarioError, match="not valid XML"):
        urdf_parents("<robot><joint>")
