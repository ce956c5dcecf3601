"""sensor_msgs/PointCloud2 <-> numpy without rospy (x, y, z float32 fields at any offsets)."""
import numpy as np

from polaris_description.errors import ConfigError

_FLOAT32 = 7


def xyz_from_cloud(msg):
    """N x 3 float array of the x, y, z fields of a PointCloud2 message (non-finite rows dropped)."""
    fields = {f.name: f for f in msg.fields}
    for name in ("x", "y", "z"):
        if name not in fields or fields[name].datatype != _FLOAT32:
            raise ConfigError("PointCloud2 has no float32 field '%s' (fields: %s)"
                              % (name, ", ".join(fields) or "none"))
    n = msg.width * msg.height
    if n == 0:
        return np.zeros((0, 3))
    dt = np.dtype(">f4" if msg.is_bigendian else "<f4")
    buf = np.frombuffer(bytes(msg.data), dtype=np.uint8)[: n * msg.point_step].reshape(n, msg.point_step)
    cols = [buf[:, fields[c].offset: fields[c].offset + 4].copy().view(dt).reshape(n)
            for c in ("x", "y", "z")]
    p = np.stack(cols, axis=1).astype(float)
    return p[np.all(np.isfinite(p), axis=1)]
