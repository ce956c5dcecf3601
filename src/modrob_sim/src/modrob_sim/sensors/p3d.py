"""gazebo_ros_p3d: ground truth of a link as nav_msgs/Odometry.

Pose of ``bodyName`` in ``frameName`` (``world``/``map`` or absent: the world; else a link of
any model, looked up by name), plus ``xyzOffsets`` (added to the position) and ``rpyOffsets``
(``offset * q``). The twist is in the WORLD frame (or, relative to a reference link, the
difference of velocities rotated as gazebo_ros_p3d does), with ``gaussianNoise`` added to its six
components; the pose and twist covariances have gaussianNoise^2 on the diagonal.
header.frame_id = frameName, child_frame_id = bodyName; ``updateRate`` Hz (0: every step).
"""
from modrob_sim.physics.transforms import quat_conj, quat_from_rpy, quat_mul, quat_normalize, quat_rotate

from .core import Rate, noise_rng
from .errors import SensorConfigError
from .sdf import Params

WORLD_FRAMES = ("world", "/world", "map", "/map", "")


class P3d(object):
    FILENAME = "libgazebo_ros_p3d.so"

    def __init__(self, world, model, plugin_elem, where, seed=None):
        p = Params(plugin_elem, where)
        body = p.string("bodyName")
        if not body:
            raise SensorConfigError("%s: <bodyName> is required" % where)
        if body not in model.links:
            p.fail("bodyName", body, "is not a link of model '%s'" % model.name)
        self.world = world
        self.link = model.links[body]
        self.body = body
        self.topic = p.string("topicName")
        if not self.topic:
            raise SensorConfigError("%s: <topicName> is required" % where)
        self.frame = p.string("frameName", "world")
        self.xyz = p.floats("xyzOffsets", 3) or p.floats("xyzOffset", 3, (0.0, 0.0, 0.0))
        rpy = p.floats("rpyOffsets", 3) or p.floats("rpyOffset", 3, (0.0, 0.0, 0.0))
        self.rot_offset = quat_from_rpy(*rpy)
        self.noise = p.float("gaussianNoise", 0.0, nonneg=True)
        self.rate = Rate(p.float("updateRate", 0.0, nonneg=True))
        self.seed = seed
        self.rng = noise_rng(world, seed)
        self.model = model
        self._where = where

    def reference_link(self):
        if self.frame in WORLD_FRAMES:
            return None
        name = self.frame.lstrip("/")
        if name in self.model.links:
            return self.model.links[name]
        for m in self.world.models.values():
            if name in m.links:
                return m.links[name]
        raise SensorConfigError("%s: <frameName> '%s' is neither world nor a link"
                                % (self._where, self.frame))

    def reset(self, reseed=True):
        if reseed and self.seed is not None:
            self.rng = noise_rng(self.world, self.seed)
        self.rate.reset()

    def step(self, t, measure=True):
        """(position, orientation, linear, angular) or None when not due (or not ``measure``d: the
        rate advances all the same)."""
        if not self.rate.due(t) or not measure:
            return None
        pos, rot = self.link.pose
        v, w = self.link.twist
        ref = self.reference_link()
        if ref is not None:
            fp, fq = ref.pose
            fv, fw = ref.twist
            inv = quat_conj(fq)
            pos = quat_rotate(inv, (pos[0] - fp[0], pos[1] - fp[1], pos[2] - fp[2]))
            rot = quat_mul(rot, inv)
            v = quat_rotate(fq, (v[0] - fv[0], v[1] - fv[1], v[2] - fv[2]))
            w = quat_rotate(fq, (w[0] - fw[0], w[1] - fw[1], w[2] - fw[2]))
        pos = (pos[0] + self.xyz[0], pos[1] + self.xyz[1], pos[2] + self.xyz[2])
        rot = quat_normalize(quat_mul(self.rot_offset, rot))
        if self.noise:
            n = self.rng.normal(0.0, self.noise, 6)
            v = (v[0] + n[0], v[1] + n[1], v[2] + n[2])
            w = (w[0] + n[3], w[1] + n[4], w[2] + n[5])
        return pos, rot, v, w

    def covariance(self):
        s2 = self.noise * self.noise
        c = [0.0] * 36
        for i in range(6):
            c[7 * i] = s2
        return c
