"""Pinhole intrinsics (Gazebo's formula), projection, zoom, and seed 000's end-effector-centred
views, equations (1)-(7): the camera sits where the equations say and the end effector is on
its optical axis."""
import math

import pytest

from modrob_viz.errors import ConfigError
from modrob_viz.render import camera_spec, ee_views, pinhole


def test_gazebo_intrinsics_formula():
    i = pinhole.gazebo_intrinsics(640, 480, 1.047)
    assert i.fx == pytest.approx(640 / (2 * math.tan(1.047 / 2)))
    assert i.fy == i.fx
    assert (i.cx, i.cy) == (320.5, 240.5)


def test_projection_and_halving_the_fov_doubles_the_size():
    i = pinhole.gazebo_intrinsics(640, 480, 1.0)
    u0, _ = pinhole.project(i, (-0.1, 0.0, 2.0))
    u1, _ = pinhole.project(i, (0.1, 0.0, 2.0))
    narrow = pinhole.zoomed(i, 2 * math.atan(math.tan(0.5) / 2))   # half the tangent: twice the focal length
    w0, _ = pinhole.project(narrow, (-0.1, 0.0, 2.0))
    w1, _ = pinhole.project(narrow, (0.1, 0.0, 2.0))
    assert (w1 - w0) == pytest.approx(2 * (u1 - u0))
    assert pinhole.project(i, (0, 0, -1)) is None


def test_hfov_round_trip():
    i = pinhole.gazebo_intrinsics(800, 600, 0.8)
    assert pinhole.hfov_from_focal(800, i.fx) == pytest.approx(0.8)


@pytest.mark.parametrize("w,h", [(0, 480), (640, 0), (-1, 5)])
def test_zero_size_camera_info_is_refused_with_a_reason(w, h):
    with pytest.raises(ConfigError, match="width and height"):
        pinhole.from_matrices(w, h, [500, 0, 320, 0, 500, 240, 0, 0, 1], None)


def test_camera_info_without_focal_length_is_refused():
    with pytest.raises(ConfigError, match="focal length"):
        pinhole.from_matrices(640, 480, [0] * 9, [0] * 12)


@pytest.mark.parametrize("hfov", [0.0, 3.2, float("nan"), "wide"])
def test_bad_hfov(hfov):
    with pytest.raises(ConfigError):
        pinhole.check_hfov(hfov)


def test_side_view_equations():
    ee = (0.4, 0.3, 1.2)
    r = 0.5
    pos, rpy = ee_views.side_view(ee, r)
    alpha = math.atan2(0.3, 0.4)                 # (1)
    dist = 0.5
    beta = math.atan2(r, dist)                   # (2)
    d = math.sqrt(dist * dist + r * r)           # (3)
    assert pos == pytest.approx((d * math.cos(alpha + beta), d * math.sin(alpha + beta), 1.2))   # (4)-(6)
    assert rpy == pytest.approx((-math.pi / 2, 0.0, math.pi + alpha))                            # (7)


@pytest.mark.parametrize("view", ee_views.VIEWS)
@pytest.mark.parametrize("ee", [(0.4, 0.3, 1.2), (-0.2, 0.5, 0.9), (0.6, -0.6, 1.5), (0.1, 0.0, 1.0)])
def test_every_view_puts_the_end_effector_on_the_axis_at_distance_r(view, ee):
    r = 0.7
    pos, rpy = ee_views.view(view, ee, r)
    x, y, z = ee_views.to_camera(pos, rpy, ee)
    assert (x, y) == pytest.approx((0.0, 0.0), abs=1e-9)
    assert z == pytest.approx(r)
    # the image x axis stays parallel to the ground (seed: xy-plane parallel to the world's)
    R = ee_views.rotation_matrix(rpy)
    assert R[2][0] == pytest.approx(0.0, abs=1e-9)


def test_quaternion_matches_matrix():
    rpy = (-math.pi / 2, 0.0, 2.5)
    qx, qy, qz, qw = ee_views.quaternion(rpy)
    R = ee_views.rotation_matrix(rpy)
    assert 1 - 2 * (qy * qy + qz * qz) == pytest.approx(R[0][0])
    assert 2 * (qx * qy - qz * qw) == pytest.approx(R[0][1])


def test_camera_specs():
    cams = camera_spec.parse_all([{"name": "ptrz/camera1", "image": "/a/image",
                                   "camera_info": "/a/camera_info"}], 10.0)
    assert cams[0]["id"] == "ptrz_camera1" and cams[0]["rate"] == 10.0 and cams[0]["format"] == "rgb8"
    with pytest.raises(ConfigError, match="no 'image'"):
        camera_spec.parse({"name": "x"}, 10.0)
    with pytest.raises(ConfigError, match="two cameras"):
        camera_spec.parse_all([{"name": "a", "image": "/i", "camera_info": "/c"}] * 2, 10.0)
    with pytest.raises(ConfigError, match="format"):
        camera_spec.parse({"name": "a", "image": "/i", "camera_info": "/c", "format": "YUV"}, 10.0)


def test_clip_distances():
    base = {"name": "a", "image": "/i", "camera_info": "/c"}
    cam = camera_spec.parse(base, 10.0)
    assert (cam["clip_near"], cam["clip_far"]) == (camera_spec.CLIP_NEAR, camera_spec.CLIP_FAR)
    cam = camera_spec.parse(dict(base, clip_near=0.5, clip_far=3.0), 10.0)
    assert (cam["clip_near"], cam["clip_far"]) == (0.5, 3.0)
    for near, far in ((0.0, 3.0), (3.0, 0.5), (-1.0, 2.0), (1.0, 1.0)):
        with pytest.raises(ConfigError, match="clip_near < clip_far"):
            camera_spec.parse(dict(base, clip_near=near, clip_far=far), 10.0)
    with pytest.raises(ConfigError, match="clip_far must be finite"):
        camera_spec.parse(dict(base, clip_far=float("nan")), 10.0)
