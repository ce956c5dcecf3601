"""Lens distortion drawn into the image (agrees with OpenCV's model of the CameraInfo's D) and the
image formats Gazebo names (16-bit, mono, bayer)."""
import numpy as np
import pytest

from modrob_viz.errors import ConfigError
from modrob_viz.render import camera_spec, lens, pinhole

INTR = pinhole.gazebo_intrinsics(160, 120, 1.0)
BARREL = (-0.25, 0.05, 0.0, 0.001, -0.002, 0.5, 0.5)


def dot_image(u, v):
    img = np.zeros((INTR.height, INTR.width, 3), np.uint8)
    img[v, u] = 255
    return img


def test_a_point_lands_where_opencv_projects_it_with_the_camera_info_d():
    cv2 = pytest.importorskip("cv2")
    k1, k2, k3, p1, p2 = BARREL[:5]
    K = np.array([[INTR.fx, 0, INTR.cx], [0, INTR.fy, INTR.cy], [0, 0, 1]])
    D = np.array([k1, k2, p1, p2, k3])          # CameraInfo's order
    maps = lens.source_maps(INTR, BARREL)
    for u, v in ((20, 15), (140, 100), (81, 61), (30, 100)):
        # OpenCV's forward model: the pinhole pixel (u, v) seen through the lens
        ray = np.array([[(u - INTR.cx) / INTR.fx, (v - INTR.cy) / INTR.fy, 1.0]])
        expected, _ = cv2.projectPoints(ray, np.zeros(3), np.zeros(3), K, D)
        out = lens.apply(dot_image(u, v), maps)[..., 0].astype(float)
        ys, xs = np.nonzero(out)
        got = (np.average(xs, weights=out[ys, xs]), np.average(ys, weights=out[ys, xs]))
        assert got == pytest.approx(tuple(expected[0, 0]), abs=0.5), (u, v)


def test_undistorting_with_the_d_gives_the_pinhole_image_back():
    cv2 = pytest.importorskip("cv2")
    k1, k2, k3, p1, p2 = BARREL[:5]
    K = np.array([[INTR.fx, 0, INTR.cx], [0, INTR.fy, INTR.cy], [0, 0, 1]])
    img = np.zeros((INTR.height, INTR.width), np.uint8)
    img[30:90, 40:120] = 200                    # a rectangle well inside the view
    back = cv2.undistort(lens.apply(img, lens.source_maps(INTR, BARREL)), K, np.array([k1, k2, p1, p2, k3]))
    assert np.mean(np.abs(back[10:110, 10:150].astype(int) - img[10:110, 10:150])) < 2.0


def test_barrel_pulls_the_corners_in_and_leaves_the_centre():
    maps = lens.source_maps(INTR, (-0.3, 0, 0, 0, 0, 0.5, 0.5))
    assert maps[0][0, 0] < 0 and maps[1][0, 0] < 0     # a corner shows what lies beyond the render
    assert maps[0][60, 80] == pytest.approx(80, abs=0.6)
    img = np.full((INTR.height, INTR.width), 100, np.uint8)
    assert lens.apply(img, maps)[0, 0] == 0              # black there, as Gazebo without borderCrop


def test_the_centre_moves_the_distortion():
    assert lens.centre(INTR, (0, 0, 0, 0, 0, 0.5, 0.5)) == (INTR.cx, INTR.cy)
    assert lens.centre(INTR, (0, 0, 0, 0, 0, 0.6, 0.5))[0] == pytest.approx(INTR.cx + 16)


def test_lens_and_trigger_keys_parsed():
    spec = dict(name="c", image="/c/image", width=160, height=120, hfov=1.0, frame="f",
                lens=dict(k1=-0.2, p2=0.01), trigger="/c/image_trigger")
    cam = camera_spec.parse(spec, 10.0)
    assert cam["lens"] == (-0.2, 0.0, 0.0, 0.0, 0.01, 0.5, 0.5)
    assert cam["trigger"] == "/c/image_trigger"
    with pytest.raises(ConfigError, match="lens"):
        camera_spec.parse(dict(spec, lens=dict(k4=1.0)), 10.0)


RGB = np.array([[[10, 20, 30], [40, 50, 60]], [[70, 80, 90], [200, 210, 220]]], np.uint8)


@pytest.mark.parametrize("fmt,enc,step,first", [
    ("mono16", "mono16", 4, round(0.299 * 10 + 0.587 * 20 + 0.114 * 30) * 257),
    ("rgb16", "rgb16", 12, 10 * 257),
    ("bayer_rggb8", "bayer_rggb8", 2, 10),
    ("bayer_bggr8", "bayer_bggr8", 2, 30),
    ("bayer_gbrg8", "bayer_gbrg8", 2, 20),
    ("mono8", "mono8", 2, int(0.299 * 10 + 0.587 * 20 + 0.114 * 30)),
])
def test_formats(fmt, enc, step, first):
    arr, encoding, got_step = camera_spec.convert(RGB, camera_spec.FORMATS[fmt])
    assert (encoding, got_step) == (enc, step)
    assert int(arr.reshape(-1)[0]) == first
    assert len(arr.tobytes()) == step * 2


def test_bayer_pattern_takes_one_colour_a_pixel():
    arr, _enc, _step = camera_spec.convert(RGB, "bayer_rggb8")
    # R at (0,0), G at (0,1) and (1,0), B at (1,1)
    assert arr.tolist() == [[10, 50], [80, 220]]
    arr, _enc, _step = camera_spec.convert(RGB, "bayer_grbg8")
    assert arr.tolist() == [[20, 40], [90, 210]]


def test_sixteen_bit_is_little_endian_full_scale():
    arr, _enc, _step = camera_spec.convert(np.full((1, 1, 3), 255, np.uint8), "mono16")
    assert arr.tobytes() == b"\xff\xff"
