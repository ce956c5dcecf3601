"""sensor_msgs/Image -> JPEG (pure: numpy + OpenCV, no rospy)."""
import cv2
import numpy as np

ENCODINGS = {"rgb8": (3, "rgb"), "bgr8": (3, "bgr"), "rgba8": (4, "rgb"), "bgra8": (4, "bgr"),
             "mono8": (1, "mono")}


class EncodingError(ValueError):
    """An image that cannot be shown (unknown encoding, wrong data size)."""


def to_bgr(width, height, encoding, step, data):
    """numpy BGR (height, width, 3) uint8 from an Image's fields."""
    if encoding not in ENCODINGS:
        raise EncodingError("image encoding %r is not supported (use one of %s)"
                            % (encoding, ", ".join(ENCODINGS)))
    channels, order = ENCODINGS[encoding]
    if width <= 0 or height <= 0 or step < width * channels or len(data) < step * height:
        raise EncodingError("image %dx%d step %d has %d bytes of data" % (width, height, step, len(data)))
    rows = np.frombuffer(data, np.uint8, step * height).reshape(height, step)
    a = rows[:, :width * channels].reshape(height, width, channels)
    if order == "mono":
        return cv2.cvtColor(a, cv2.COLOR_GRAY2BGR)
    if order == "rgb":
        return np.ascontiguousarray(a[:, :, 2::-1])
    return np.ascontiguousarray(a[:, :, :3])


def jpeg(bgr, quality=95, width=0, height=0):
    """JPEG bytes, resized when width/height are given (one of them keeps the aspect ratio)."""
    if width > 0 or height > 0:
        h, w = bgr.shape[:2]
        if width <= 0:
            width = max(1, int(round(w * height / float(h))))
        if height <= 0:
            height = max(1, int(round(h * width / float(w))))
        bgr = cv2.resize(bgr, (width, height))
    ok, buf = cv2.imencode(".jpg", bgr, [int(cv2.IMWRITE_JPEG_QUALITY), int(max(1, min(100, quality)))])
    if not ok:
        raise EncodingError("OpenCV could not encode the image as JPEG")
    return buf.tobytes()
