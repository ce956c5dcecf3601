"""Tier 1: a depth camera's depth image and point cloud from a render's depth and colour.

A synthetic render of a wall 2 m ahead (z = 2 everywhere) with nothing drawn in one corner: the
depth image keeps what is within Gazebo's cutoffs, the cloud's points lie on the wall plane where
the pinhole model puts each pixel, and a point projected back with the CameraInfo intrinsics lands
on its own pixel (the cloud agrees with the depth image + CameraInfo, as depth_image_proc reads
them)."""
import math

import numpy as np
import pytest

from modrob_viz.errors import ConfigError
from modrob_viz.render import camera_spec, depth, pinhole

W, H = 8, 6
INTR = pinhole.gazebo_intrinsics(W, H, 1.0)


def _render():
    d = np.full((H, W), 2.0, np.float32)
    d[0, 0] = np.inf                   # nothing drawn
    d[1, 1] = 0.3                      # nearer than the 0.4 m cutoff
    d[2, 2] = 6.0                      # beyond openni_kinect's 5 m
    rgb = np.zeros((H, W, 3), np.uint8)
    rgb[..., 0] = 200
    rgb[..., 2] = 10
    return d, rgb


def test_cutoffs_as_openni_kinect_and_depth_camera():
    d, _ = _render()
    kinect = depth.masked(d, 0.4, 5.0)
    assert np.isnan(kinect[0, 0]) and np.isnan(kinect[1, 1]) and np.isnan(kinect[2, 2])
    assert kinect[3, 3] == pytest.approx(2.0)
    plain = depth.masked(d, 0.4)       # depth_camera: no upper cutoff
    assert plain[2, 2] == pytest.approx(6.0) and np.isnan(plain[1, 1]) and np.isinf(plain[0, 0])


def test_depth_image_encodings():
    d, _ = _render()
    kept = depth.masked(d, 0.4, 5.0)
    arr, enc, step = depth.depth_image(kept, "32FC1")
    assert (enc, step, arr.dtype.str) == ("32FC1", W * 4, "<f4")
    arr, enc, step = depth.depth_image(kept, "16UC1")
    assert (enc, step, arr.dtype.str) == ("16UC1", W * 2, "<u2")
    assert arr[3, 3] == 2000 and arr[0, 0] == 0 and arr[1, 1] == 0
    with pytest.raises(ValueError):
        depth.depth_image(kept, "8UC1")


def test_cloud_points_on_the_wall_where_the_pinhole_puts_them():
    d, rgb = _render()
    kept = depth.masked(d, 0.4, 5.0)
    rays = depth.pixel_rays(W, H, INTR.fx, INTR.fy, INTR.cx, INTR.cy)
    pts, dense = depth.point_cloud(kept, rgb, rays)
    assert not dense and pts.dtype.itemsize == depth.POINT_STEP == 32
    assert pts.shape == (W * H,)
    grid = pts.reshape(H, W)
    for v in range(H):
        for u in range(W):
            p = grid[v, u]
            if np.isnan(kept[v, u]):
                assert math.isnan(p["z"])
                continue
            assert p["z"] == pytest.approx(2.0)
            uu, vv = pinhole.project(INTR, (float(p["x"]), float(p["y"]), float(p["z"])))
            assert (uu, vv) == (pytest.approx(u, abs=1e-4), pytest.approx(v, abs=1e-4))
    # colour packed as PCL and RViz read it: 0x00RRGGBB
    assert grid[3, 3]["rgb"] == (200 << 16) | 10


def test_cloud_bytes_layout():
    d, rgb = _render()
    rays = depth.pixel_rays(W, H, INTR.fx, INTR.fy, INTR.cx, INTR.cy)
    pts, _ = depth.point_cloud(depth.masked(d, 0.0), rgb, rays)
    raw = pts.tobytes()
    assert len(raw) == W * H * 32
    x, y, z = np.frombuffer(raw[32 * 27:32 * 27 + 12], "<f4")
    assert z == pytest.approx(2.0)
    assert raw[32 * 27 + 16:32 * 27 + 20] == bytes([10, 0, 200, 0])     # b, g, r, 0


def test_depth_keys_of_a_camera_spec():
    spec = camera_spec.parse({"name": "kinect", "image": "/camera/rgb/image_raw", "camera_info": "/ci",
                              "depth_image": "/camera/depth/image_raw", "points": "/camera/depth/points",
                              "point_cloud_cutoff": 0.4, "point_cloud_cutoff_max": 5.0}, 10.0)
    assert spec["depth"] and spec["depth_format"] == "32FC1"
    assert (spec["point_cloud_cutoff"], spec["point_cloud_cutoff_max"]) == (0.4, 5.0)
    plain = camera_spec.parse({"name": "c", "image": "/i", "camera_info": "/ci"}, 10.0)
    assert not plain["depth"] and plain["point_cloud_cutoff_max"] == math.inf


@pytest.mark.parametrize("bad, text", [({"depth_format": "8UC1"}, "depth_format"),
                                       ({"point_cloud_cutoff": 3.0, "point_cloud_cutoff_max": 2.0},
                                        "must be below")])
def test_bad_depth_keys_named(bad, text):
    spec = dict({"name": "k", "image": "/i", "camera_info": "/ci", "depth_image": "/d"}, **bad)
    with pytest.raises(ConfigError, match=text):
        camera_spec.parse(spec, 10.0)
