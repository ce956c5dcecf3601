"""Gazebo's ray sensor (``<sensor type="ray">`` and ``type="gpu_ray"``): ray geometry from the
SDF ``<ray>`` block, ranges as Gazebo reports them.

Gazebo's reporting (RaySensor / GpuRaySensor, REP 117): a beam whose range is >= ``<range><max>``
(nothing hit) reads ``+inf``, one <= ``<range><min>`` reads ``-inf``; every other beam gets the
``<noise>`` (gaussian: + N(mean, stddev)) and is then clamped to [min, max]. Ray ``i`` of row
``j`` has yaw ``min_angle + i (max_angle - min_angle) / (n - 1)`` and pitch likewise from the
``<vertical>`` block (pitch up positive); ranges are stored row by row (index ``j * n + i``).
``<resolution>`` multiplies the samples (Gazebo interpolates; here every range is cast).
"""
import math

import numpy as np

from modrob_sim.physics.transforms import quat_to_matrix

from .core import MountedSensor, noise_rng
from .errors import SensorConfigError
from .raycast import make_caster
from .sdf import Params


class RaySpec(object):
    """The <ray> (or <lidar>) block of a sensor."""

    def __init__(self, sensor_elem, where):
        p = Params(sensor_elem, where)
        base = "ray" if p.has("ray") else ("lidar" if p.has("lidar") else None)
        if base is None:
            raise SensorConfigError("%s: a %s sensor needs a <ray> block"
                                    % (where, sensor_elem.get("type")))
        self.h_samples = p.int(base + "/scan/horizontal/samples", 640, minimum=1)
        self.h_resolution = p.float(base + "/scan/horizontal/resolution", 1.0, positive=True)
        self.h_min = p.float(base + "/scan/horizontal/min_angle", 0.0)
        self.h_max = p.float(base + "/scan/horizontal/max_angle", 0.0)
        self.v_samples = p.int(base + "/scan/vertical/samples", 1, minimum=1)
        self.v_resolution = p.float(base + "/scan/vertical/resolution", 1.0, positive=True)
        self.v_min = p.float(base + "/scan/vertical/min_angle", 0.0)
        self.v_max = p.float(base + "/scan/vertical/max_angle", 0.0)
        self.range_min = p.float(base + "/range/min", 0.0, nonneg=True)
        self.range_max = p.float(base + "/range/max", 10.0, positive=True)
        self.range_resolution = p.float(base + "/range/resolution", 0.0, nonneg=True)
        if self.range_max <= self.range_min:
            p.fail(base + "/range/max", self.range_max,
                   "must be greater than <range><min> %g" % self.range_min)
        if self.h_max < self.h_min:
            p.fail(base + "/scan/horizontal/max_angle", self.h_max, "is below <min_angle> %g" % self.h_min)
        if self.v_max < self.v_min:
            p.fail(base + "/scan/vertical/max_angle", self.v_max, "is below <min_angle> %g" % self.v_min)
        ntype = p.string(base + "/noise/type", "none").lower()
        if ntype not in ("none", "gaussian", ""):
            p.fail(base + "/noise/type", ntype, "is not supported (gaussian or none)")
        self.noise_mean = p.float(base + "/noise/mean", 0.0)
        self.noise_stddev = p.float(base + "/noise/stddev", 0.0, nonneg=True)
        if ntype in ("none", ""):
            self.noise_mean = self.noise_stddev = 0.0
        # Gazebo's counts: samples * resolution (at least one)
        self.count = max(1, int(round(self.h_samples * self.h_resolution)))
        self.v_count = max(1, int(round(self.v_samples * self.v_resolution)))

    @property
    def angle_step(self):
        return (self.h_max - self.h_min) / (self.count - 1) if self.count > 1 else 0.0

    @property
    def v_angle_step(self):
        return (self.v_max - self.v_min) / (self.v_count - 1) if self.v_count > 1 else 0.0

    def yaws(self):
        return self.h_min + self.angle_step * np.arange(self.count)

    def pitches(self):
        return self.v_min + self.v_angle_step * np.arange(self.v_count)

    def local_dirs(self):
        """(v_count * count, 3) unit directions in the sensor frame, row by row."""
        pitch, yaw = np.meshgrid(self.pitches(), self.yaws(), indexing="ij")
        c = np.cos(pitch)
        return np.ascontiguousarray(np.stack([c * np.cos(yaw), c * np.sin(yaw), np.sin(pitch)], -1)
                                    .reshape(-1, 3))


class RaySensor(MountedSensor):
    """A ray sensor on a link: ``scan()`` -> (ranges, intensities), Gazebo's reporting."""

    def __init__(self, world, model, link_name, sensor_elem, filename=None, caster=None, seed=None):
        MountedSensor.__init__(self, model, link_name, sensor_elem, filename)
        self.world = world
        self.spec = RaySpec(sensor_elem, self.where)
        self._dirs = self.spec.local_dirs()
        self._dirs.flags.writeable = False      # fixed: the caster keeps what it derives from them
        self.caster = make_caster(world, exclude=[(model.name, link_name)], kind=caster)
        self.seed = seed
        self.rng = noise_rng(world, seed)
        self._retro = {}
        self._table = (None, None)

    def reseed(self):
        if self.seed is not None:
            self.rng = noise_rng(self.world, self.seed)

    def raw_ranges(self):
        """Distances to the first hit (inf: none) and the hit geom index per ray."""
        pos, rot = self.pose()
        R = quat_to_matrix(rot)
        return self.caster.cast(pos, R, self._dirs, self.spec.range_min, self.spec.range_max,
                                want_hits=True)

    @property
    def ray_count(self):
        return self._dirs.shape[0]

    def scan(self):
        """(ranges, intensities) at this instant, as Gazebo reports them."""
        return self.prepare_scan()()

    def prepare_scan(self):
        """scan() in two halves: this instant's pose, geometry and noise now; the function returned
        casts the rays and gives (ranges, intensities), called once, later and from another thread
        if need be (a sensor plugin's publishing build), while the World steps on."""
        s = self.spec
        pos, rot = self.pose()
        cast = self.caster.prepare(pos, quat_to_matrix(rot), self._dirs, s.range_min, s.range_max,
                                   want_hits=True)
        # one draw per ray, whatever it hits: the noise stream does not depend on the scene
        noise = self.rng.normal(s.noise_mean, s.noise_stddev, self.ray_count) if s.noise_stddev > 0 else None
        table = self._retro_table(cast.labels)

        def finish():
            r, hits = cast.run()
            out = r.copy()
            hi = out >= s.range_max
            lo = out <= s.range_min
            if noise is not None or s.noise_mean != 0:
                mid = ~(hi | lo)
                out[mid] += noise[mid] if noise is not None else s.noise_mean
                np.clip(out, s.range_min, s.range_max, out=out)
            out[hi] = math.inf
            out[lo] = -math.inf
            return out, table[np.where(hits >= 0, hits, len(table) - 1)]
        return finish

    def intensities(self, hits):
        """Gazebo's ray intensities: the <laserRetro> of the link that was hit (0 if none)."""
        table = self._retro_table(self.caster.labels)
        return table[np.where(hits >= 0, hits, len(table) - 1)]

    def _retro_table(self, labels):
        """The <laserRetro> of each hit index's link, then 0 for no hit (kept while the caster's
        labels are the same list)."""
        kept, table = self._table
        if kept is not labels:
            table = np.zeros(len(labels) + 1)
            for k, (m, ln) in enumerate(labels):
                table[k] = self._retro_of(m, ln)
            self._table = (labels, table)
        return table

    def _retro_of(self, model_name, link_name):
        key = (model_name, link_name)
        if key not in self._retro:
            v = 0.0
            m = self.world.models.get(model_name)
            ln = m.links.get(link_name) if m is not None else None
            e = getattr(ln, "extra", {}).get("laserRetro") if ln is not None else None
            if e is not None:
                try:
                    v = float((e.text or "0").strip())
                except ValueError:
                    v = 0.0
            self._retro[key] = v
        return self._retro[key]
