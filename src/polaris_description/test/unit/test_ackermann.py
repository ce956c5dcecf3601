"""Ackermann core: the seed's formula, the geometry (both axes meet the rear axle line), limits."""
import math

import pytest

from polaris_description import geometry as G
from polaris_description.ackermann import (Ackermann, max_curvature, radius_of, seed_angles,
                                           steering_angles)
from polaris_description.errors import CommandError


@pytest.mark.parametrize("radius", [2.5, 5.0, 10.0, 40.0])
def test_matches_the_seed_formula_for_right_turns(radius):
    alpha_l, alpha_r = seed_angles(radius)
    delta_l, delta_r = steering_angles(-1.0 / radius)
    assert delta_l == pytest.approx(-alpha_l, abs=1e-12)
    assert delta_r == pytest.approx(-alpha_r, abs=1e-12)


@pytest.mark.parametrize("radius", [-20.0, -5.0, -2.2, 2.2, 5.0, 20.0])
def test_both_front_axes_meet_the_rear_axle_line_at_the_centre(radius):
    dl, dr = steering_angles(1.0 / radius)
    rl, rr = radius_of(dl, dr)
    assert rl == pytest.approx(radius, abs=1e-9)
    assert rr == pytest.approx(radius, abs=1e-9)


def test_inner_wheel_steers_more():
    dl, dr = steering_angles(1.0 / 5.0)      # left turn: left is the inner wheel
    assert dl > dr > 0
    dl, dr = steering_angles(-1.0 / 5.0)
    assert dr < dl < 0


def test_straight_is_the_limit():
    c = Ackermann().command(1.0, 0.0)
    assert (c.steer_left, c.steer_right) == (0.0, 0.0)
    assert c.rear_left == c.rear_right == pytest.approx(1.0 / G.WHEEL_RADIUS)
    tiny = Ackermann().command(1.0, 1e-9)
    assert abs(tiny.steer_left) < 1e-8 and abs(tiny.steer_left - tiny.steer_right) < 1e-12


def test_rear_wheels_follow_their_own_circles():
    c = Ackermann().command(1.0, 0.2)        # R = 5 m, left
    r = G.WHEEL_RADIUS
    assert c.rear_left * r == pytest.approx((5.0 - G.REAR_TRACK / 2) / 5.0)
    assert c.rear_right * r == pytest.approx((5.0 + G.REAR_TRACK / 2) / 5.0)


def test_curvature_is_clamped_to_the_steering_limit():
    a = Ackermann()
    c = a.command(1.0, 5.0)
    assert c.clamped
    assert max(abs(c.steer_left), abs(c.steer_right)) == pytest.approx(G.STEER_LIMIT, abs=1e-9)
    assert c.curvature == pytest.approx(max_curvature())


def test_zero_speed_keeps_the_steering_and_stops_the_wheels():
    a = Ackermann()
    first = a.command(1.0, 0.2)
    c = a.command(0.0, 0.0)
    assert c.rear_left == c.rear_right == 0.0
    assert c.steer_left == pytest.approx(first.steer_left)


def test_same_angle_baseline_is_the_seeds_setup():
    c = Ackermann(same_angle=True).command(1.0, 0.2)
    assert c.steer_left == c.steer_right == pytest.approx(math.atan(G.WHEELBASE * 0.2))
    assert c.rear_left == c.rear_right


@pytest.mark.parametrize("v,w", [(float("nan"), 0.0), (1.0, float("inf"))])
def test_non_finite_commands_are_refused_with_the_field_named(v, w):
    with pytest.raises(CommandError, match="linear.x|angular.z"):
        Ackermann().command(v, w)


def test_bad_dimensions_are_named():
    with pytest.raises(CommandError, match="wheelbase"):
        Ackermann(wheelbase=0.0)
