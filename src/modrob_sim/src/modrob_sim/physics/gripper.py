"""Gazebo's ``<gripper>`` grasp check (SDF ``<model><gripper>``, URDF ``<gazebo><gripper>``):
an object held by the gripper links for long enough is welded to the palm link, and let go when
the contact has been gone for long enough. As gazebo::physics::Gripper:

* every UPDATE_PERIOD (Gazebo: 0.75 s of wall time; here of simulated time, so that runs are
  deterministic) the contacts seen since the last update are counted: ``min_contact_count`` or
  more counts one up (and resets the "no contact" count), fewer counts one down and the "no
  contact" count one up;
* when the count exceeds ``attach_steps``, an object link touched from two sides (by at least two
  different gripper links, or one gripper link at two contacts where only one is listed) whose
  pose relative to the palm has kept still (squared displacement per update below 1e-5 m^2 over
  the last 10 updates) is welded to the palm with a fixed joint;
* when the "no contact" count exceeds ``detach_steps``, the joint goes.

Only movable links count (Gazebo filters static collisions too). Defaults as SDF's:
attach_steps 20, detach_steps 40, min_contact_count 2.

Gazebo's gripper collects the contacts of EVERY step between its updates. So does this one,
without Python at every step: a contact watch on the gripper links (``World.watch_contacts``)
notes the pairs where the backend makes the contacts, and the check is an after-step hook due at
its next update (and at once after a reset or when the held object was deleted), so the steps in
between run natively.
"""
import logging
import math
import weakref
from collections import deque, namedtuple

LOG = logging.getLogger("modrob_sim.physics")

UPDATE_PERIOD = 0.75
STABLE_SAMPLES = 10
STABLE_DISPLACEMENT2 = 1e-5

GripperDesc = namedtuple("GripperDesc", "name gripper_links palm_link attach_steps detach_steps "
                                        "min_contact_count")


def read_gripper(rd, elem, where, local):
    """GripperDesc from a <gripper> Element (``rd``: the reader's checked number parsing)."""
    name = elem.get("name") or "gripper"
    w = "%s <gripper name='%s'>" % (where, name)

    def child(parent, tag):
        for c in parent:
            if local(c.tag) == tag:
                return c
        return None

    gc = child(elem, "grasp_check")
    values = {"attach_steps": 20, "detach_steps": 40, "min_contact_count": 2}
    if gc is not None:
        for tag in values:
            e = child(gc, tag)
            if e is not None:
                v = rd.float((e.text or "").strip(), w, "<%s>" % tag)
                if v < 0 or v != int(v) or v > 1e6:
                    rd.fail(w, "<%s> must be a whole number in [0, 1e6], got %s" % (tag, e.text))
                values[tag] = int(v)
    links = [(c.text or "").strip() for c in elem if local(c.tag) == "gripper_link"]
    palm = child(elem, "palm_link")
    if not links or palm is None or not (palm.text or "").strip():
        rd.fail(w, "needs at least one <gripper_link> and a <palm_link>")
    return GripperDesc(name, tuple(links), palm.text.strip(), values["attach_steps"],
                       values["detach_steps"], values["min_contact_count"])


class Gripper(object):
    """The run-time grasp check of one <gripper> of a spawned model (an after-step hook)."""

    def __init__(self, world, model, desc):
        # weak, as Model's: the World must be collectable (its finalizer frees ODE in order)
        self.world = weakref.proxy(world)
        self.model = weakref.proxy(model)
        self.desc = desc
        self.palm = model.links[desc.palm_link]
        self.links = frozenset(desc.gripper_links)
        self.attached = None      # (object model, object link name) while welded
        self._joint = None
        self._pos = 0
        self._zero = 0
        self._next = world.time + UPDATE_PERIOD
        self._resets = world.reset_count
        self._prev_rel = None
        self._diffs = deque([float("inf")] * STABLE_SAMPLES, maxlen=STABLE_SAMPLES)
        # the contacts of every step between two updates (static collisions are not noted)
        self._watch = world.watch_contacts([model.links[n] for n in desc.gripper_links])
        me = weakref.ref(self)

        def hook(t, dt):
            g = me()
            if g is not None:
                g.after_step(t, dt)

        def due():
            g = me()
            return g.after_due() if g is not None else math.inf
        self._hook = world.add_step_hook(after=hook, after_due=due)

    # -- the hook ----------------------------------------------------------------------------
    def after_due(self):
        """The next update; now (None) after a reset or when the held object was deleted, so that
        the gripper lets go at the next step."""
        if self.world.reset_count != self._resets or (self.attached is not None and self.attached[0].removed):
            return None
        return self._next

    def after_step(self, t, dt):
        if self.model.removed:
            self.close()
            return
        if self.world.reset_count != self._resets:  # reset / reset_world: let go, count again
            self._resets = self.world.reset_count
            self._detach("the world was reset")
            self._pos = self._zero = 0
            self._next = t + UPDATE_PERIOD      # (the World dropped what the watch had seen)
        if self.attached is not None and self.attached[0].removed:
            self._detach("model '%s' was deleted" % self.attached[0].name)
        if t + 1e-9 >= self._next:             # the World's rule for due times
            self._next += UPDATE_PERIOD
            self._update(self._contacts())

    def _contacts(self):
        """{(gripper link, object model, object link)} touched at any step since the last update
        (the gripper links touching each other do not count)."""
        me = self.model.name
        return set((s.link, s.other_model, s.other_link) for s in self._watch.drain()
                   if not (s.other_model == me and s.other_link in self.links))

    def _update(self, seen):
        if len(seen) >= self.desc.min_contact_count:
            self._pos += 1
            self._zero = 0
        else:
            self._zero += 1
            self._pos = max(0, self._pos - 1)
        if self._pos > self.desc.attach_steps and self.attached is None:
            self._try_attach(seen)
        elif self._zero > self.desc.detach_steps and self.attached is not None:
            self._detach("no contact for %d updates" % self._zero)

    def _try_attach(self, seen):
        sides = {}
        for glink, mn, ln in seen:
            sides.setdefault((mn, ln), set()).add(glink)
        need = 2 if len(self.links) > 1 else 1
        for (mn, ln), glinks in sorted(sides.items()):
            if len(glinks) < need:
                continue
            obj = self.world.models[mn].links[ln]
            rel = _relative_position(self.palm, obj)
            if self._prev_rel is not None:
                d = [a - b for a, b in zip(rel, self._prev_rel)]
                self._diffs.append(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            self._prev_rel = rel
            if max(self._diffs) < STABLE_DISPLACEMENT2:
                self._attach(self.world.models[mn], obj)
            return

    def _attach(self, obj_model, obj_link):
        if obj_link.body is None:
            return
        self._joint = self.world.weld(obj_link, self.palm)  # a static palm: to the world
        self.attached = (obj_model, obj_link.name)
        LOG.info("model '%s' gripper '%s': attached model '%s' link '%s' to palm link '%s'",
                 self.model.name, self.desc.name, obj_model.name, obj_link.name, self.palm.name)

    def _detach(self, why):
        if self._joint is None:
            self.attached = None
            return
        self._joint.release()
        self._joint = None
        obj = self.attached
        self.attached = None
        self._diffs.extend([float("inf")] * STABLE_SAMPLES)
        self._prev_rel = None
        LOG.info("model '%s' gripper '%s': released model '%s' link '%s' (%s)",
                 self.model.name, self.desc.name, obj[0].name, obj[1], why)

    def close(self):
        """Let go and stop checking (the model was deleted)."""
        if self._joint is not None:
            self._joint.release()
            self._joint = None
        self.attached = None
        self._watch.close()
        if self._hook is not None:
            try:
                self.world.remove_step_hook(self._hook)
            except (ValueError, ReferenceError):
                pass  # the World is being torn down
            self._hook = None


def _relative_position(palm, link):
    (pp, pq), lp = palm.pose, link.pose[0]
    d = (lp[0] - pp[0], lp[1] - pp[1], lp[2] - pp[2])
    # in the palm frame: rotate by the inverse of the palm's orientation
    x, y, z, w = pq
    return _rotate((-x, -y, -z, w), d)


def _rotate(q, v):
    x, y, z, w = q
    tx = 2.0 * (y * v[2] - z * v[1])
    ty = 2.0 * (z * v[0] - x * v[2])
    tz = 2.0 * (x * v[1] - y * v[0])
    return (v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz),
            v[2] + w * tz + (x * ty - y * tx))
