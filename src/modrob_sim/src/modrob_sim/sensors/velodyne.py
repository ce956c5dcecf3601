"""sensor_msgs/PointCloud2 of velodyne_simulator's gazebo_ros_velodyne_laser (and _gpu_laser).

Layout (22-byte points, little endian): x y z intensity float32 at 0 4 8 12, ring uint16 at 16,
time float32 at 18. For each horizontal sample i (outer loop) and each laser j (inner loop, ring
j, 0 = lowest pitch): the range r of ray (j, i); a point is kept when
max(min_range, <range><min>) < r < min(max_range, <range><max>) (and intensity >= min_intensity);
then gaussianNoise is added to r and x = r cos(p) cos(y), y = r cos(p) sin(y), z = r sin(p);
time 0. Unorganized (default): height 1, width = points, is_dense true. organize_cloud: beams out
of range become NaN points, width = lasers, height = samples, is_dense false.
"""
import numpy as np

POINT_STEP = 22
POINT_DTYPE = np.dtype({"names": ["x", "y", "z", "intensity", "ring", "time"],
                        "formats": ["<f4", "<f4", "<f4", "<f4", "<u2", "<f4"],
                        "offsets": [0, 4, 8, 12, 16, 18], "itemsize": POINT_STEP})
# (name, offset, datatype, count): PointField FLOAT32 = 7, UINT16 = 4
FIELDS = (("x", 0, 7, 1), ("y", 4, 7, 1), ("z", 8, 7, 1), ("intensity", 12, 7, 1), ("ring", 16, 4, 1),
          ("time", 18, 7, 1))


class VelodyneConfig(object):
    def __init__(self, params, spec):
        self.min_range = params.float("min_range", 0.0)
        self.max_range = params.float("max_range", float("inf"))
        self.gaussian_noise = params.float("gaussianNoise", 0.0, nonneg=True)
        self.organize_cloud = params.bool("organize_cloud", False)
        self.min_intensity = params.float("min_intensity", -np.finfo(np.float64).max)
        self.lo = max(self.min_range, spec.range_min)
        self.hi = min(self.max_range, spec.range_max)


def pack_cloud(spec, cfg, ranges, intensities, rng=None, noise=None):
    """(data bytes, width, height, row_step, is_dense) from row-major ranges (v_count x count)
    as Gazebo reports them (+-inf out of range). The range noise is ``noise`` (row-major, drawn
    beforehand) or drawn from ``rng`` (N(0, gaussianNoise))."""
    nv, nh = spec.v_count, spec.count
    r = np.asarray(ranges, dtype=np.float64).reshape(nv, nh).T      # [i][j]: horizontal outer
    inten = np.asarray(intensities, dtype=np.float64).reshape(nv, nh).T
    valid = (r > cfg.lo) & (r < cfg.hi) & (inten >= cfg.min_intensity)
    if noise is not None:
        r = r + np.asarray(noise, dtype=np.float64).reshape(nv, nh).T
    elif cfg.gaussian_noise:
        r = r + rng.normal(0.0, cfg.gaussian_noise, r.shape)
    in_band = (r > cfg.lo) & (r < cfg.hi)        # the plugin checks again after the noise
    valid = in_band if cfg.organize_cloud else (valid & in_band)
    pitch = spec.pitches()[None, :]
    yaw = spec.yaws()[:, None]
    cp = np.cos(pitch)
    if cfg.organize_cloud:
        pts = np.zeros((nh, nv), dtype=POINT_DTYPE)
        nan = np.float32("nan")
        pts["x"] = np.where(valid, r * cp * np.cos(yaw), nan)
        pts["y"] = np.where(valid, r * cp * np.sin(yaw), nan)
        pts["z"] = np.where(valid, r * np.sin(pitch), nan)
        pts["intensity"] = np.where(valid, inten, nan)
        pts["ring"] = np.arange(nv, dtype=np.uint16)[None, :]
        return pts.tobytes(), nv, nh, POINT_STEP * nv, False
    ii, jj = np.nonzero(valid)                 # row-major: i outer, j inner, as the plugin
    rv = r[ii, jj]
    pts = np.zeros(len(rv), dtype=POINT_DTYPE)
    pv = pitch[0, jj]
    yv = yaw[ii, 0]
    pts["x"] = rv * np.cos(pv) * np.cos(yv)
    pts["y"] = rv * np.cos(pv) * np.sin(yv)
    pts["z"] = rv * np.sin(pv)
    pts["intensity"] = inten[ii, jj]
    pts["ring"] = jj
    data = pts.tobytes()
    return data, len(rv), 1, len(data), True
