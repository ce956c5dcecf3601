"""Image -> JPEG conversions of web_video_server (no ROS master)."""
import cv2
import numpy as np
import pytest

from web_video_server.encoding import EncodingError, jpeg, to_bgr


def test_rgb_becomes_bgr_and_round_trips_through_jpeg():
    rgb = np.zeros((20, 30, 3), np.uint8)
    rgb[..., 0] = 250                      # red
    bgr = to_bgr(30, 20, "rgb8", 90, rgb.tobytes())
    assert bgr[0, 0].tolist() == [0, 0, 250]
    img = cv2.imdecode(np.frombuffer(jpeg(bgr, 90), np.uint8), 1)
    assert img.shape == (20, 30, 3) and img[10, 15, 2] > 200


def test_mono_and_padded_rows():
    data = bytes(bytearray(range(4)) + b"\0\0") * 2     # 4 px wide, step 6
    bgr = to_bgr(4, 2, "mono8", 6, data)
    assert bgr[1, 3].tolist() == [3, 3, 3]


def test_resize_keeps_aspect():
    bgr = np.zeros((40, 80, 3), np.uint8)
    img = cv2.imdecode(np.frombuffer(jpeg(bgr, 80, width=40), np.uint8), 1)
    assert img.shape[:2] == (20, 40)


@pytest.mark.parametrize("enc,size", [("yuv422", 100), ("rgb8", 5)])
def test_bad_images_name_the_problem(enc, size):
    with pytest.raises(EncodingError):
        to_bgr(4, 4, enc, 12, bytes(size))
