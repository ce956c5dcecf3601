"""Colour segmentation of the tracked ball with OpenCV: HSV thresholds, a morphological opening,
the largest blob, its centroid (image moments)."""
from collections import namedtuple

import cv2
import numpy as np

Detection = namedtuple("Detection", "u v area")

#: HSV range of the ball (OpenCV: H 0..180, S and V 0..255): a saturated magenta, a colour nothing
#: else in the worlds has (the seed's pole is Gazebo/Orange, its camera link red).
MAGENTA = ((140, 120, 70), (170, 255, 255))


class BallFinder(object):
    def __init__(self, hsv_low=MAGENTA[0], hsv_high=MAGENTA[1], min_area=6):
        self.low = np.array(hsv_low, dtype=np.uint8)
        self.high = np.array(hsv_high, dtype=np.uint8)
        self.min_area = min_area
        self.kernel = np.ones((3, 3), np.uint8)

    def mask(self, rgb):
        hsv = cv2.cvtColor(rgb, cv2.COLOR_RGB2HSV)
        m = cv2.inRange(hsv, self.low, self.high)
        return cv2.morphologyEx(m, cv2.MORPH_OPEN, self.kernel)

    def find(self, rgb):
        """Detection (centroid u, v in pixels, whole numbers at pixel centres as in ROS's CameraInfo,
        area in px) or None."""
        m = self.mask(rgb)
        n, labels, stats, centroids = cv2.connectedComponentsWithStats(m, 8)
        if n <= 1:
            return None
        best = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
        area = int(stats[best, cv2.CC_STAT_AREA])
        if area < self.min_area:
            return None
        cu, cv_ = centroids[best]
        return Detection(float(cu), float(cv_), area)
