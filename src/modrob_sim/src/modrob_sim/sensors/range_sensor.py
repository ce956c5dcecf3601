"""Range finders on a ray sensor: gazebo_ros_range (libgazebo_ros_range.so, sonar or infrared)
and hector_gazebo_ros_sonar (libhector_gazebo_ros_sonar.so) give the nearest of the sensor's rays
as sensor_msgs/Range; gazebo_ros_block_laser (libgazebo_ros_block_laser.so) gives every ray as a
point of a sensor_msgs/PointCloud.

A ray that hits nothing reads ``<range><max>`` here, as Gazebo's ray shape reports it to these
plugins. gazebo_ros_range: the nearest reading, below the maximum plus N(0, ``gaussianNoise``)
and at most the maximum. hector's sonar: the nearest reading, below the maximum through hector's
error model (sensor_model.SensorModel, no prefix) and clamped to [min, max]; its field of view
is the smaller of the horizontal and vertical spans. Block laser: each ray's point
(r cos(pitch) cos(yaw), r cos(pitch) sin(yaw), r sin(pitch)) in the sensor frame, N(0,
``gaussianNoise``) added to each coordinate unless the ray reads the maximum, and the hit link's
``<laserRetro>`` plus noise as the intensity channel.
"""
import math

import numpy as np

from .core import Rate
from .sdf import Params
from .sensor_model import SensorModel


def nearest(ranges, range_max):
    """The nearest of ``ranges`` (inf: nothing hit) as Gazebo's ray shape reports it."""
    r = float(np.min(ranges)) if len(ranges) else math.inf
    return min(r, range_max)


class GazeboRange(object):
    """gazebo_ros_range's reading of a RaySensor."""

    def __init__(self, ray, plugin_elem, where):
        p = Params(plugin_elem, where)
        self.ray = ray
        self.topic = p.string("topicName", "/range")
        self.frame = p.string("frameName", "/world")
        self.radiation = p.string("radiation", "ultrasound").lower()
        self.fov = p.float("fov", 0.05, nonneg=True)
        self.noise = p.float("gaussianNoise", 0.0, nonneg=True)
        self.rate = Rate(p.float("updateRate", 0.0, nonneg=True))

    def read(self):
        s = self.ray.spec
        r = nearest(self.ray.raw_ranges()[0], s.range_max)
        if r < s.range_max and self.noise > 0:
            r = min(r + self.ray.rng.normal(0.0, self.noise), s.range_max)
        return r


class HectorSonar(object):
    """hector_gazebo_ros_sonar's reading of a RaySensor (updateRate 10 Hz by default)."""

    def __init__(self, ray, plugin_elem, where):
        p = Params(plugin_elem, where)
        self.ray = ray
        self.topic = p.string("topicName", "sonar")
        self.frame_id = p.string("frameId", "/sonar_link")
        self.model = SensorModel(p, "", ray.rng, axes=1)
        self.rate = Rate(p.float("updateRate", 10.0, nonneg=True))
        s = ray.spec
        self.fov = min(abs(s.h_max - s.h_min), abs(s.v_max - s.v_min))
        self.last_t = None

    def reset(self):
        """After the ray sensor's reseed (or not): a new drift from the sensor's generator."""
        self.model.rng = self.ray.rng
        self.model.reset()
        self.rate.reset()
        self.last_t = None

    def read(self, t):
        """The range at an update at simulated time ``t`` (hector's update timer decides when)."""
        dt = t - self.last_t if self.last_t is not None and t > self.last_t else 0.0
        self.last_t = t
        s = self.ray.spec
        r = nearest(self.ray.raw_ranges()[0], s.range_max)
        if r < s.range_max:
            r = min(max(self.model.apply((r,), dt)[0], s.range_min), s.range_max)
        return r


class BlockLaser(object):
    """gazebo_ros_block_laser's cloud of a RaySensor: (points (n, 3) float32, intensities (n,))."""

    def __init__(self, ray, plugin_elem, where):
        p = Params(plugin_elem, where)
        self.ray = ray
        self.topic = p.string("topicName", "/world")
        self.frame = p.string("frameName", "/world")
        self.noise = p.float("gaussianNoise", 0.0, nonneg=True)
        p.float("hokuyoMinIntensity", 101.0)     # accepted (the original reads it and does not use it)
        self.rate = Rate(p.float("updateRate", 0.0, nonneg=True))
        dirs = ray.spec.local_dirs()
        self._dirs = dirs

    def read(self):
        s = self.ray.spec
        r, hits = self.ray.raw_ranges()
        r = np.minimum(r, s.range_max)
        points = self._dirs * r[:, None]
        intensities = self.ray.intensities(hits)
        if self.noise > 0:
            rng = self.ray.rng
            hit = np.abs(s.range_max - r) > 1e-6
            points[hit] += rng.normal(0.0, self.noise, (int(hit.sum()), 3))
            intensities = intensities + rng.normal(0.0, self.noise, intensities.shape)
        return points.astype(np.float32), intensities.astype(np.float32)
