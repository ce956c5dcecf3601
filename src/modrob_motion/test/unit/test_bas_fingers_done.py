"""outcome.fingers_done: when the scenario may go on after a gripper command (its joint_states show
the command took effect), so that a lift never starts with the fingers still open."""
import numpy as np

from modrob_motion.bulbs_and_slides.outcome import fingers_done

GOAL = [0.0]            # closed on nothing
LIMIT = [3.0]           # the grip force


def test_at_the_goal_is_done_whatever_the_effort():
    assert fingers_done([0.0015], GOAL, [0.1], LIMIT, None)
    assert fingers_done([0.05], [0.05], [0.0], None, None)


def test_open_fingers_with_no_effort_are_not_done():
    # the sample from before the close command landed: open, still, no squeeze
    assert not fingers_done([0.05], GOAL, [0.02], LIMIT, [0.0])


def test_stopped_on_the_object_at_the_grip_force_is_done():
    assert fingers_done([0.0295], GOAL, [3.0], LIMIT, [0.0003])
    assert fingers_done([0.0295], GOAL, [-2.5], LIMIT, [0.0])      # the sign of the effort does not matter


def test_still_moving_or_not_pressing_hard_enough_is_not_done():
    assert not fingers_done([0.031], GOAL, [3.0], LIMIT, [0.001])     # closing at 50 mm/s
    assert not fingers_done([0.0295], GOAL, [2.0], LIMIT, [0.0])
    assert not fingers_done([0.0295], GOAL, [3.0], LIMIT, None)     # no previous fresh sample yet


def test_every_finger_must_be_done_and_unknown_limits_only_count_the_goal():
    assert not fingers_done([0.0295, 0.05], [0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 0.0])
    assert not fingers_done([0.0295], GOAL, [3.0], [np.nan], [0.0])
    assert fingers_done([0.0], GOAL, [3.0], [np.nan], [0.0])
