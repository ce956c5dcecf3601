"""Gazebo's contact sensor with gazebo_ros_bumper -> gazebo_msgs/ContactsState.

Each update reports the contacts the physics made in the last step that involve a collision of
the sensor's link (every collision of the link; Gazebo names URDF collisions
``<link>_collision``), one ContactState per pair of links: collision1_name is the sensor's
collision (``model::link::link_collision``), collision2_name the other one; positions, normals
(pointing from the other body into the sensor's, as ODE reports them for geom 1) and depths, in
the world frame (``frameName`` world) or in the frame of the link named ``frameName``; the
wrench each contact applied to the sensor's body in the step (the physics core's contact forces,
ODE's contact joint feedback; torque about the centre of mass of the sensor link's body), in the
same frame. (Gazebo's ODE gives these forces in the sensor link's frame whatever ``frameName``
says; the two agree while the link is level.)

Sleeping bodies make no contacts in ODE, so a box resting on the sensor would vanish from it
once the physics auto-disables it: a body seen touching the sensor is kept awake (its
auto-disable flag is turned off), and so is the sensor's own body.
"""
from collections import OrderedDict

from modrob_sim.physics import world as world_mod
from modrob_sim.physics.transforms import quat_conj, quat_rotate

from .core import MountedSensor, Rate
from .sdf import Params


class ContactPair(object):
    __slots__ = ("collision1", "collision2", "positions", "normals", "depths", "forces", "torques")

    def __init__(self, c1, c2):
        self.collision1, self.collision2 = c1, c2
        self.positions, self.normals, self.depths = [], [], []
        self.forces, self.torques = [], []

    def total(self):
        """(force, torque): the sums over the pair's contacts."""
        return (tuple(sum(f[k] for f in self.forces) for k in range(3)),
                tuple(sum(t[k] for t in self.torques) for k in range(3)))


def collision_name(model, link):
    return "%s::%s::%s_collision" % (model, link, link)


class ContactSensor(MountedSensor):
    FILENAME = "libgazebo_ros_bumper.so"

    def __init__(self, world, model, link_name, sensor_elem, plugin_elem, filename=FILENAME):
        MountedSensor.__init__(self, model, link_name, sensor_elem, filename)
        p = Params(plugin_elem, self.where)
        self.world = world
        self.topic = p.string("bumperTopicName", "bumper_states")
        self.frame = p.string("frameName", "world")
        self.rate = Rate(self.update_rate)
        self._awake = set()
        elems = sensor_elem.iter() if sensor_elem is not None else []
        self.collisions = [(c.text or "").strip() for c in elems
                           if isinstance(c.tag, str) and c.tag == "collision"]

    def reset(self):
        self.rate.reset()

    def frame_pose(self):
        name = self.frame.lstrip("/")
        if name in ("world", "map", ""):
            return None
        if name in self.model.links:
            return self.model.links[name].pose
        for m in self.world.models.values():
            if name in m.links:
                return m.links[name].pose
        return None

    def contacts(self):
        """OrderedDict (collision1, collision2) -> ContactPair from the last physics step."""
        me_m, me_l = self.model.name, self.link.name
        fp = self.frame_pose()
        inv = quat_conj(fp[1]) if fp is not None else None
        out = OrderedDict()
        self._keep_awake(self.link)
        for c in self.world.contacts():
            if (c.model1, c.link1) == (me_m, me_l):
                other, n, f, tq = (c.model2, c.link2), c.normal, c.force1, c.torque1
            elif (c.model2, c.link2) == (me_m, me_l):
                other, n = (c.model1, c.link1), (-c.normal[0], -c.normal[1], -c.normal[2])
                f, tq = c.force2, c.torque2
            else:
                continue
            self._keep_awake(self._link(*other))
            key = (collision_name(me_m, me_l), collision_name(*other))
            pair = out.get(key)
            if pair is None:
                pair = out[key] = ContactPair(*key)
            pos = c.position
            if fp is not None:
                pos = quat_rotate(inv, (pos[0] - fp[0][0], pos[1] - fp[0][1], pos[2] - fp[0][2]))
                n = quat_rotate(inv, n)
                f, tq = quat_rotate(inv, f), quat_rotate(inv, tq)
            pair.positions.append(tuple(pos))
            pair.normals.append(tuple(n))
            pair.depths.append(c.depth)
            pair.forces.append(tuple(f))
            pair.torques.append(tuple(tq))
        return out

    def _link(self, model_name, link_name):
        m = self.world.models.get(model_name)
        return m.links.get(link_name) if m is not None else None

    def _keep_awake(self, link):
        body = link.body if link is not None else None
        if body is not None and body not in self._awake:
            world_mod._set_auto_disable(body, False)
            self._awake.add(body)

    def step(self, t):
        if not self.rate.due(t):
            return None
        return self.contacts()
