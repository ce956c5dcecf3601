"""``/gazebo/model_states`` and ``/gazebo/link_states`` serialised once per world layout and sent
through roscpp (gazebo_ros.native_pub) without building rospy messages.

At 100 Hz of simulated time and ten or more times real time, building the two messages in Python
(a Pose and a Twist object per model and per link, Link.pose and Link.twist, then rospy's
serialisation) cost the node more per step than the collision detection. The messages have no
header, so their bytes are fixed but for the float64s: :class:`StatesMessage` keeps the serialised
message of one layout of the world (names, counts), and the physics core's ``mr_link_poses``
(physics/native/modrob_ode_native.c) writes every pose and twist into its two arrays of doubles,
computed exactly as Link.pose and Link.twist compute them (the bytes are rospy's,
``test_native_states.py`` compares them). The physics knows links and doubles; this module knows
the message.

Used only with the C loop (native backend) and roscpp publishing; the rospy messages stay the path
otherwise.
"""
import ctypes
import struct

from modrob_sim.physics import native as native_mod
from modrob_sim.physics import odelib


class _Entry(ctypes.Structure):
    """MrLinkEntry: a link's body and its frame in the body frame (static: its world pose)."""
    _fields_ = [("body", ctypes.c_void_p), ("T", ctypes.c_double * 7)]


def _declare(lib):
    """mr_link_poses of ``lib`` with its signature, or None."""
    if lib is None or not hasattr(lib, "mr_link_poses"):
        return None
    f = lib.mr_link_poses
    f.restype = None
    f.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p]
    return f


_POSES = _declare(native_mod.LIB_HELD)   # keep the GIL: microseconds, in the simulation thread


def available(world):
    return _POSES is not None and getattr(world, "native", False) is True


def _names_blob(names):
    out = [struct.pack("<I", len(names))]
    for n in names:
        b = n.encode("utf-8")
        out.append(struct.pack("<I", len(b)) + b)
    return b"".join(out)


class StatesMessage(object):
    """The serialised ModelStates or LinkStates of ``links`` named ``names`` (one physics Link per
    entry: a model's entry is its canonical link). ``publish(publisher)`` fills in the poses and
    twists of now and publishes (a NativePublisher)."""

    def __init__(self, names, links):
        n = len(names)
        head = _names_blob(names)
        pose0 = len(head) + 4
        twist0 = pose0 + 56 * n + 4
        self.size = twist0 + 48 * n
        self._buf = (ctypes.c_uint8 * self.size)()
        ctypes.memmove(self._buf, head + struct.pack("<I", n), pose0)
        struct.pack_into("<I", self._buf, pose0 + 56 * n, n)
        base = ctypes.addressof(self._buf)
        self._poses, self._twists = base + pose0, base + twist0
        self._entries = (_Entry * max(1, n))()
        self._n = n
        self._static = []       # (entry, link, the static pose tuple last written)
        for k, ln in enumerate(links):
            e = self._entries[k]
            body = ln.body
            if body is None:
                e.body = None
                self._static.append([e, ln, None])
            else:
                e.body = odelib.raw_pointer(body)
                p, q = ln.body_offset
                e.T[:] = tuple(p) + tuple(q)

    def _refresh_static(self):
        for item in self._static:
            e, ln, last = item
            pose = ln.pose      # raises as Link.pose does when the link has left the world
            if pose is not last:
                e.T[:] = tuple(pose[0]) + tuple(pose[1])
                item[2] = pose

    def write(self):
        """The poses and twists of now into the message."""
        self._refresh_static()
        _POSES(self._entries, self._n, self._poses, self._twists)

    def publish(self, publisher):
        self.write()
        publisher.publish_serialized(self._buf, self.size)

    def serialized(self):
        """The message's bytes as of now (tests)."""
        self.write()
        return bytes(self._buf)


def model_states(world):
    models = list(world.models.items())
    return StatesMessage([name for name, _m in models], [m.canonical_link for _n, m in models])


def link_states(world):
    names, links = [], []
    for mname, model in world.models.items():
        for lname, link in model.links.items():
            names.append("%s::%s" % (mname, lname))
            links.append(link)
    return StatesMessage(names, links)
