"""Gazebo's ``<gripper>`` grasp check (SDF ``<model><gripper>``, URDF ``<gazebo><gripper>``):
an object held by the gripper links for long enough is welded to the palm link, and let go when
the contact has been gone for long enough. The rules are gazebo::physics::Gripper's (Gazebo 11):

* between two updates every step's contacts of the gripper links' collisions are collected, ONE
  per colliding pair of collisions per step (Gazebo's contact manager makes one contact message
  per pair and step), both sides on a body (Gazebo drops a pair with a static collision); two
  gripper collisions touching each other make one contact too;
* every UPDATE_PERIOD (Gazebo: 0.75 s of wall time since the last update; here of simulated
  time, on a fixed grid from the gripper's spawn, so that runs are deterministic) the number of
  contacts collected counts: ``min_contact_count`` or more counts one up (and the "no contact"
  count back to 0), fewer counts one down (not below 0) and the "no contact" count one up. So
  one finger touching an object for two steps is enough for the default of 2;
* when the count exceeds ``attach_steps`` and nothing is held: each collision that is not a
  gripper collision and appears in at least 2 of the collected contacts is a candidate, taken in
  the order of its scoped name (``model::link::collision``). For each, until one is welded: its
  link's position relative to the palm (in the palm frame) is compared with the previous
  candidate's (the origin at first), the squared displacement goes into ONE ring of the last 10
  (shared by all candidates: two objects touched at once keep each other from being welded), and
  when every entry is below 1e-5 m^2 the link is welded to the palm with a fixed joint;
* when the "no contact" count exceeds ``detach_steps`` while holding, the joint goes; the ring
  and the previous position stay as they are (Gazebo resets neither).

Where this differs from Gazebo (docs/physics.md): simulated time; a reset (reset, reset_world)
lets go and starts the counts, the ring and the previous position afresh; a held object that is
deleted is let go at the next step; a link welded to the world counts as static (it has no body
here). Defaults as SDF's: attach_steps 20, detach_steps 40, min_contact_count 2.

The contacts of every step are collected without Python at every step: a contact watch on the
gripper links (``World.watch_contacts``) counts, per pair of collisions, the steps in which the
pair made contacts, where the backend makes them; the check is an after-step hook due at its next
update (and at once after a reset or when the held object was deleted), so the steps in between
run natively.
"""
import logging
import math
import weakref
from collections import deque, namedtuple

from .due import is_due

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
        self._restart_ring()
        # the contacts of every step between two updates (static collisions are not noted). A
        # static gripper link (no body: a static model's, or welded to the world) counts nothing,
        # as Gazebo drops a pair with a static collision.
        self._watch = world.watch_contacts([model.links[n] for n in desc.gripper_links])
        self._static = frozenset(n for n in desc.gripper_links if model.links[n].body is None)
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
        if self.world.reset_count != self._resets:  # reset / reset_world: let go, count afresh
            self._resets = self.world.reset_count
            self._detach("the world was reset")
            self._pos = self._zero = 0
            self._restart_ring()
            self._next = t + UPDATE_PERIOD      # (the World dropped what the watch had seen)
        if self.attached is not None and self.attached[0].removed:
            self._detach("model '%s' was deleted" % self.attached[0].name)
        if is_due(t, self._next):
            self._next += UPDATE_PERIOD
            self._update(self._contacts())

    def _contacts(self):
        """The SeenContacts of the gripper links since the last update: per pair of collisions,
        the steps in which it made contacts (none of a static gripper link)."""
        return [s for s in self._watch.drain() if s.link not in self._static]

    def _restart_ring(self):
        """The stillness ring full of 'not still' and the previous position at the palm's origin,
        as a newly loaded Gazebo gripper has them."""
        self._prev_rel = (0.0, 0.0, 0.0)
        self._diffs = deque([float("inf")] * STABLE_SAMPLES, maxlen=STABLE_SAMPLES)

    def _is_gripper(self, model_name, link_name):
        return model_name == self.model.name and link_name in self.links

    def contact_count(self, seen):
        """Gazebo's contacts collected between two updates: one per pair of collisions per step.
        A pair of two gripper collisions is in ``seen`` both ways round; it counts once."""
        n = 0
        for s in seen:
            if self._is_gripper(s.other_model, s.other_link) and \
                    (s.other_link, s.other_collision) < (s.link, s.collision):
                continue
            n += s.steps
        return n

    def _update(self, seen):
        if self.contact_count(seen) >= self.desc.min_contact_count:
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
        counts = {}
        for s in seen:
            if self._is_gripper(s.other_model, s.other_link):
                continue
            key = "%s::%s::%s" % (s.other_model, s.other_link, s.other_collision)
            n = counts.get(key, (s.other_model, s.other_link, 0))
            counts[key] = (n[0], n[1], n[2] + s.steps)
        for key in sorted(counts):
            mn, ln, n = counts[key]
            if n < 2:
                continue
            model = self.world.models.get(mn)
            obj = model.links.get(ln) if model is not None else None
            if obj is None:
                continue
            rel = _relative_position(self.palm, obj)
            d = [a - b for a, b in zip(rel, self._prev_rel)]
            self._prev_rel = rel
            self._diffs.append(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            if max(self._diffs) < STABLE_DISPLACEMENT2:
                self._attach(model, obj)
                if self.attached is not None:
                    return

    def _attach(self, obj_model, obj_link):
        if obj_link.body is None or obj_link.body is self.palm.body:
            return      # nothing to weld (a link of the palm's own body, with self-collision)
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
