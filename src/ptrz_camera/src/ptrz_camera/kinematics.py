"""Forward kinematics of the PTRZ camera from its URDF (world -> camera link through pan, tilt,
roll) and aiming: the pan and tilt that put a world point on the optical axis. Pure numpy."""
import math
import xml.etree.ElementTree as ET

import numpy as np

from ptrz_camera.errors import ConfigError


def rot_rpy(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def rot_axis(axis, angle):
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k.dot(k)


def transform(rot, t):
    m = np.eye(4)
    m[:3, :3] = rot
    m[:3, 3] = t
    return m


class CameraChain(object):
    """The joints from ``world`` to the camera link: list of (name, type, origin 4x4, axis)."""

    def __init__(self, urdf_xml, camera_link=None):
        try:
            root = ET.fromstring(urdf_xml)
        except ET.ParseError as exc:
            raise ConfigError("camera URDF does not parse: %s" % exc)
        by_child = {}
        for j in root.findall("joint"):
            origin = j.find("origin")
            xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
            rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
            axis = j.find("axis")
            ax = [float(v) for v in axis.get("xyz").split()] if axis is not None else [1.0, 0.0, 0.0]
            by_child[j.find("child").get("link")] = (j.get("name"), j.get("type"),
                                                     j.find("parent").get("link"),
                                                     transform(rot_rpy(*rpy), xyz), ax)
        if camera_link is None:
            cams = [c for c in by_child if c == "camera" or c.endswith("_camera")]
            if len(cams) != 1:
                raise ConfigError("camera URDF: cannot tell the camera link (found %s); name it" % cams)
            camera_link = cams[0]
        chain = []
        link = camera_link
        while link in by_child:
            name, jtype, parent, origin, axis = by_child[link]
            chain.append((name, jtype, origin, axis))
            link = parent
        if link != "world":
            raise ConfigError("camera URDF: link %s is not connected to 'world'" % camera_link)
        self.camera_link = camera_link
        self.joints = list(reversed(chain))
        names = [j[0] for j in self.joints if j[1] != "fixed"]
        if not {"pan", "tilt", "roll"} <= set(names):
            raise ConfigError("camera URDF: joints pan, tilt, roll expected between world and %s, found %s"
                              % (camera_link, names))

    def pose(self, q):
        """(R, t) of the camera link in the world for joint positions ``q`` (dict)."""
        m = np.eye(4)
        for name, jtype, origin, axis in self.joints:
            m = m.dot(origin)
            if jtype != "fixed":
                m = m.dot(transform(rot_axis(axis, q.get(name, 0.0)), (0, 0, 0)))
        return m[:3, :3], m[:3, 3]

    def frame_before(self, joint_name, q):
        """4x4 world pose of a joint's frame (its origin applied, its motion not)."""
        m = np.eye(4)
        for name, jtype, origin, axis in self.joints:
            m = m.dot(origin)
            if name == joint_name:
                return m
            if jtype != "fixed":
                m = m.dot(transform(rot_axis(axis, q.get(name, 0.0)), (0, 0, 0)))
        raise KeyError(joint_name)

    def aim(self, target, q):
        """(pan, tilt) that put ``target`` (world point) on the optical axis, pan the nearest to
        q["pan"]; None if no pan/tilt can (a point closer to the pan axis than the tilt arm's
        offset). Closed form for the seed's structure: the pan axis is vertical (z of its frame),
        the tilt axis is y of the pan frame and the optical axis (+x of the camera, also the
        roll axis) crosses the tilt axis; so the target must lie in the plane y = b of the pan
        frame (b = the tilt axis' offset), which gives pan, and tilt is the elevation from the
        tilt axis."""
        target = np.asarray(target, dtype=float)
        m_pan = self.frame_before("pan", {})
        local = np.linalg.inv(m_pan).dot(np.append(target, 1.0))[:3]        # pan frame at pan = 0
        m_tilt = np.linalg.inv(m_pan).dot(self.frame_before("tilt", {}))    # tilt frame in the pan frame
        a = m_tilt[:3, 3]
        rho = math.hypot(local[0], local[1])
        if rho <= abs(a[1]) + 1e-9:
            return None
        alpha = math.atan2(local[1], local[0])
        pan = alpha - math.asin(a[1] / rho)
        x_in_pan = math.sqrt(rho * rho - a[1] * a[1])
        tilt = math.atan2(-(local[2] - a[2]), x_in_pan - a[0])
        here = q.get("pan", 0.0)
        pan += 2.0 * math.pi * round((here - pan) / (2.0 * math.pi))
        return pan, tilt
