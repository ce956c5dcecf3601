"""The RESULT line and YAML of a Bulbs and Slides run report the set-point stream's late set-points
and the simulator-alone reference only when there is something to say."""
import math

from modrob_motion.bulbs_and_slides.scenario import Result


def test_line_without_stream_figures():
    r = Result()
    r.success, r.sim_time, r.wall_time = True, 20.0, 10.0
    line = r.line("one_robot")
    assert line.startswith("RESULT one_robot: SUCCESS, sim time 20.00 s, wall 10.0 s (real-time factor 2.00)")
    assert "late" not in line and "alone" not in line


def test_line_and_dict_with_late_setpoints_and_reference():
    r = Result()
    r.sim_time, r.wall_time = 20.0, 10.0
    r.setpoints, r.late_setpoints, r.sim_alone_rtf = 1400, 61, 2.5
    r.message = "the bulb is not in the gripper after the lift"
    line = r.line("one_robot")
    assert "FAILURE" in line
    assert ", 61 of 1400 set-points late, simulator alone 2.50 -- the bulb" in line
    d = r.as_dict()
    assert (d["setpoints"], d["late_setpoints"], d["sim_alone_rtf"]) == (1400, 61, 2.5)
    assert math.isnan(Result().as_dict()["sim_alone_rtf"])


def test_holding_spans_the_first_close_to_the_last_open(monkeypatch):
    from modrob_motion.bulbs_and_slides import scenario
    clock = {"sim": 10.0, "wall": 100.0}
    monkeypatch.setattr(scenario.rospy, "get_time", lambda: clock["sim"])
    monkeypatch.setattr(scenario.time, "time", lambda: clock["wall"])
    r = Result()
    r.holding(False)                            # an open before any close: nothing held
    assert r.as_dict()["held_sim_time"] == 0.0
    r.holding(True)
    clock.update(sim=12.0, wall=100.5)
    r.holding(True)                             # a second robot closing later: still from the first
    clock.update(sim=16.0, wall=102.0)
    r.holding(False)
    d = r.as_dict()
    assert (d["held_sim_time"], d["held_wall_time"]) == (6.0, 2.0)


def test_lift_offset_keeps_the_largest_of_the_lifts():
    r = Result()
    assert math.isnan(r.as_dict()["lift_offset"])       # no lift yet (a run that failed before it)
    r.lifted(0.004)
    r.lifted(0.0125)                                    # the second robot's lift slipped more
    r.lifted(0.001)
    assert r.as_dict()["lift_offset"] == 0.0125


def test_line_tells_late_joint_states_from_half_a_second():
    r = Result()
    r.sim_time, r.wall_time, r.success = 20.0, 10.0, True
    r.js_lag = 0.3
    assert "joint_states" not in r.line("one_robot")
    r.js_lag = 2.44
    assert r.line("one_robot").endswith("placement error nan mm, joint_states up to 2.4 s late")
    assert r.as_dict()["js_lag"] == 2.44
