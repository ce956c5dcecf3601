"""Tier 1: the two-robot clearance geometry (skeleton segments from a URDF, segment distances)."""
import math
import os

import numpy as np
import pytest

from modrob_motion.bulbs_and_slides import ScenarioError
from modrob_motion.bulbs_and_slides.clearance import (clearance, positions_by_model, segment_distance,
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


# ---- the two-robot layout numbers and the socket-first placement reference ----------------------------
LAYOUT_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "modrob_description",
                           "worlds", "bulbs_and_slides_layout.yaml")


def two_robot_layout():
    from modrob_motion.bulbs_and_slides.layout import Layout
    return Layout.load("two_robots", LAYOUT_FILE)


def test_cradle_is_one_arm_length_from_both_shoulders_and_the_bases_keep_the_safety_distance():
    lay = two_robot_layout()
    (_, b0), (_, b1) = lay.robots
    assert math.dist(b0[:2], b1[:2]) > 2 * lay.safety_distance
    d0, d1 = (math.dist(b[:2], lay.cradle_point[:2]) for b in (b0, b1))
    assert d0 == pytest.approx(d1, abs=1e-6)


def test_socket_first_rest_lies_one_socket_length_further_up_than_glass_first():
    from modrob_motion.bulbs_and_slides.outcome import expected_rest
    lay = two_robot_layout()
    glass_first = expected_rest(lay, "blue_slide", 1)
    socket_first = expected_rest(lay, "blue_slide", 1, socket_first=True)
    shift = lay.bulb_length - 2 * lay.grasp_offset
    assert np.linalg.norm(socket_first - glass_first) == pytest.approx(shift, abs=1e-9)
    assert np.dot(socket_first - glass_first, lay.slides["blue_slide"].uphill) > 0


def arm_gap_to_waiting_bulbs(lay, robot, slide):
    """Gap (m; negative = overlap) between a 3-DoF arm at its release pose and the glass of every bulb
    the layout has waiting at ``slide``'s tip; inf when none waits there. The arm, from the module
    database: a cylinder of its largest module radius from the pitch (elbow) axis, pointing at the
    place point, out to the gripper; a bulb's glass, the cylinder of expected_rest's glass centre."""
    from modrob_build.module_database import load_database
    from modrob_motion.bulbs_and_slides.outcome import expected_rest
    db = load_database()
    order, base = lay.robots[robot]
    modules = [db[i] for i in order]
    k = next(i for i, m in enumerate(modules) if m.kind == "joint_elbow")
    shoulder = np.array(base, dtype=float) + [0.0, 0.0, sum(m.length for m in modules[:k]) +
                                              modules[k].joint_offset]
    after = modules[k + 1:]
    length = modules[k].length - modules[k].joint_offset + sum(m.length for m in after)
    radius = max(m.radius for m in [modules[k]] + after)
    towards = (lay.place_point - shoulder) / np.linalg.norm(lay.place_point - shoulder)
    u = lay.slides[slide].uphill
    gap = math.inf
    for i in range(lay.bulbs_waiting_on(slide)):
        c = expected_rest(lay, slide, i)
        d = segment_distance(shoulder, shoulder + length * towards, c - 0.5 * lay.glass_length * u,
                             c + 0.5 * lay.glass_length * u)
        gap = min(gap, d - radius - lay.glass_radius)
    return gap


def layout_with_a_bulb_under_modrob1s_arm():
    """The two-robot layout as it was until the release aborted: a bulb waiting at the blue slide's
    tip, the release point 0.2 m further up the slide (its numbers as the generator wrote them)."""
    import yaml
    from modrob_motion.bulbs_and_slides.layout import Layout
    with open(LAYOUT_FILE) as fh:
        data = yaml.safe_load(fh)
    lay = data["layouts"]["two_robots"]
    lay["bulbs_on"] = dict(lay["bulbs_on"], bulb_3="blue_slide")
    lay["slides"]["blue_slide"].update(tip=[-0.682617, 0.64, 1.06], high_end=[-0.337934, 0.64, 1.120777])
    lay["place_point"] = [-0.462331, 0.64, 1.149614]
    return Layout(data, "two_robots", LAYOUT_FILE)


def test_no_bulb_waits_under_modrob1s_arm_at_the_release():
    """modrob1 reaches the release point with its arm about horizontal at the bulbs' height, so its
    long tube passes low over the blue slide. The bulb the world had waiting at that slide's tip lay
    45 mm inside the tube: once the contact correction followed Gazebo's (whole penetration in
    position) the tube stopped on it instead of sinking into its glass, and the trajectory
    controller aborted the release (joint2 'still moving' at the capped solve's velocity)."""
    assert arm_gap_to_waiting_bulbs(layout_with_a_bulb_under_modrob1s_arm(), 1, "blue_slide") < -0.03
    assert arm_gap_to_waiting_bulbs(two_robot_layout(), 1, "blue_slide") > 0.005


def test_modrob1_sets_the_bulb_down_just_uphill_of_where_it_rests():
    """Released 0.2 m up the slide, the bulb (socket first after the hand-over) slid under modrob1's
    retreating arm and stuck at the tongue's start or was knocked off; set down on the post, its
    socket landed on top of it. The release point lies 5-30 mm uphill of the socket-first rest
    against the post (behind the bulbs waiting there), at most a drop of 30 mm above it."""
    from modrob_motion.bulbs_and_slides.outcome import expected_rest
    lay = two_robot_layout()
    slide = lay.slides["blue_slide"]
    rest = expected_rest(lay, "blue_slide", lay.bulbs_waiting_on("blue_slide"), socket_first=True)
    along, across, up = (a - b for a, b in zip(slide.coordinates(lay.place_point), slide.coordinates(rest)))
    assert 0.005 <= along <= 0.03
    assert abs(across) < 1e-6
    assert 0.0 < up <= 0.03


def test_layouts_say_which_bulbs_wait_on_which_slide():
    lay = two_robot_layout()
    assert lay.bulbs_waiting_on("red_slide") == 3 and lay.bulbs_waiting_on("blue_slide") == 0
    from modrob_motion.bulbs_and_slides.layout import Layout
    one = Layout.load("one_robot", LAYOUT_FILE)
    assert one.bulbs_waiting_on("red_slide") == 3 and one.bulbs_waiting_on("blue_slide") == 1


def test_paths_plot_writes_a_png(tmp_path):
    from modrob_motion.bulbs_and_slides.paths_plot import plot_paths
    lay = two_robot_layout()
    t = np.linspace(0.0, 1.0, 30)
    arc = np.stack([-1.1 + 0.64 * np.cos(t), -0.64 + 0.64 * np.sin(t), 1.1 + 0 * t], axis=1)
    out = plot_paths(str(tmp_path / "paths.png"), lay, {0: (t, arc), 1: (t, arc[::-1])}, closest=(0.6, "x"))
    with open(out, "rb") as fh:
        assert fh.read(8) == b"\x89PNG\r\n\x1a\n"
