"""Point transforms with a geometry_msgs/TransformStamped (numpy, no tf2_geometry_msgs needed)."""
import numpy as np


def apply_transform(tf, p):
    """Transform point p by a geometry_msgs TransformStamped."""
    t, r = tf.transform.translation, tf.transform.rotation
    x, y, z, w = r.x, r.y, r.z, r.w
    rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    return rot.dot(np.asarray(p, float)) + np.array([t.x, t.y, t.z])
