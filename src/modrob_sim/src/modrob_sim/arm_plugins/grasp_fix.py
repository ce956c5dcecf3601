"""gazebo-pkgs' ``libgazebo_grasp_fix.so`` (gazebo_grasp_plugin, Noetic): an object held between
opposing gripper contacts is fixed to the palm link, and let go when the fingers have left it.

Configuration as the original reads it::

    <arm> (one or more)  <arm_name> (unique), <palm_link>, <gripper_link> (one or more)
    <forces_angle_tolerance>  degrees (120): two contact forces on an object further apart than
                              this, the smaller at least 0.3 of the larger, make a grip
    <update_rate>             Hz (5): how often the contacts are judged
    <max_grip_count>          (10) the grip count's ceiling
    <grip_count_threshold>    (floor(max_grip_count / 2)) counts above it attach
    <release_tolerance>       m (0.005): how far a finger's original contact point may have moved
                              from the object before the object is let go
    <disable_collisions_on_attach>  (false) the held object's collisions off while attached
    <contact_topic>           accepted (Gazebo's transport topic; contacts come from the physics)

At each update the contacts of the physics step (with their forces, ``World.contacts``) between a
gripper link and any other moving link are grouped per object link and gripper link: the mean
force on the object, the mean contact point and the object's position in the gripper link's
frame. An object whose forces make a grip counts up (to max_grip_count), else down; above the
threshold it is attached (``World.weld``) to the palm of the arm with the most links touching it,
unless one of the arms touching it holds something already. An attached object whose count has
fallen to the threshold is released when, for any of the links that gripped it, the distance from
the link's original contact point to the object has changed by more than release_tolerance.

Differences: the original decimates by wall-clock time and averages the contacts of every step
since the last update; here the update runs at its rate in simulated time (the same in every run,
however fast the machine) on the contacts of the step it runs after, so the physics steps natively
in between.
"""
import logging
import math

from modrob_sim.errors import PluginError
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin, RateGate
from modrob_sim.gazebo_ros.plugins import register_plugin
from modrob_sim.physics.transforms import quat_conj, quat_rotate

FILENAME = "libgazebo_grasp_fix.so"
LENGTH_RATIO = 0.3
LOG = logging.getLogger("modrob_sim.grasp_fix")


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _norm(v):
    return math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


def _in_frame(pose, point):
    """``point`` (world) in the frame of ``pose``."""
    return quat_rotate(quat_conj(pose[1]), _sub(point, pose[0]))


def is_grip(forces, min_angle, length_ratio=LENGTH_RATIO):
    """True when two of ``forces`` are more than ``min_angle`` (rad) apart and the shorter is at
    least ``length_ratio`` of the longer (forces below 1e-4 N do not count)."""
    for i, a in enumerate(forces):
        la = _norm(a)
        if la < 1e-4:
            continue
        for b in forces[i + 1:]:
            lb = _norm(b)
            if lb < 1e-4:
                continue
            c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb)
            if math.acos(max(-1.0, min(1.0, c))) > min_angle and min(la, lb) / max(la, lb) >= length_ratio:
                return True
    return False


class Arm(object):
    """One <arm>: its palm link, its gripper links and the weld of what it holds."""

    def __init__(self, name, palm, links):
        self.name, self.palm, self.links = name, palm, links
        self.weld = None
        self.held = None              # (model name, link name) while attached
        self.grip_points = {}         # gripper link -> (contact point, object position), link frame


class GraspFix(ModelPlugin):
    def load(self, model, spec, context):
        self.world = context.world
        self.disable_collisions = (self.param("disable_collisions_on_attach", "false").lower()
                                   in ("true", "1"))
        tol = self.param("forces_angle_tolerance", 120.0, float)
        if tol < 90.0:
            raise PluginError("%s: <forces_angle_tolerance> %g: two forces make a grip only when more "
                              "than 90 degrees apart (the original refuses every grip below that); "
                              "give at least 90, e.g. 100" % (self.name, tol))
        self.min_angle = math.radians(tol)
        rate = self.param("update_rate", 5, int)
        if rate <= 0:
            raise PluginError("%s: <update_rate> must be a positive whole number of Hz" % self.name)
        self.gate = RateGate(float(rate))
        self.max_grip_count = self.param("max_grip_count", 10, int)
        self.threshold = self.param("grip_count_threshold", int(math.floor(self.max_grip_count / 2.0)), int)
        self.release_tolerance = self.param("release_tolerance", 0.005, float)
        self.param("contact_topic", "")      # accepted: Gazebo's transport topic
        self.arms = self._read_arms(model)
        self.link_arm = {ln: arm for arm in self.arms for ln in arm.links}
        self.counts = {}                      # object (model, link) -> grip count

    def _read_arms(self, model):
        arms, names = [], set()
        elems = self.element.findall("arm")
        if not elems:
            raise PluginError("%s: no <arm> given; write <arm><arm_name>..</arm_name><palm_link>.."
                              "</palm_link><gripper_link>..</gripper_link></arm> (several <arm> blocks "
                              "for several grippers)" % self.name)
        for k, e in enumerate(elems):
            name = self.param("arm_name", "", element=e)
            palm = self.param("palm_link", "", element=e)
            fingers = [(g.text or "").strip() for g in e.findall("gripper_link") if (g.text or "").strip()]
            if not (name and palm and fingers):
                LOG.error("%s: <arm> %d lacks one of <arm_name>, <palm_link>, <gripper_link>; skipped",
                          self.name, k + 1)
                continue
            if name in names:
                LOG.error("%s: arm '%s' is given twice; the second is skipped", self.name, name)
                continue
            if palm not in model.links:
                LOG.error("%s: arm '%s': palm link '%s' is not a link of model '%s'; the arm is skipped",
                          self.name, name, palm, model.name)
                continue
            links = []
            for f in fingers:
                if f not in model.links:
                    LOG.error("%s: arm '%s': gripper link '%s' is not a link of model '%s'; skipped",
                              self.name, name, f, model.name)
                elif not model.links[f].collisions:
                    LOG.error("%s: arm '%s': gripper link '%s' has no collision; skipped", self.name, name, f)
                else:
                    links.append(f)
            if not links:
                LOG.error("%s: arm '%s' has no gripper link with a collision; skipped", self.name, name)
                continue
            names.add(name)
            arms.append(Arm(name, model.links[palm], frozenset(links)))
        if not arms:
            raise PluginError("%s: no <arm> could be set up (see the errors above)" % self.name)
        return arms

    # ---- the update ---------------------------------------------------------------------------
    def after_due(self):
        return self.gate.next_time

    def after_step(self, t, dt):
        if not self.gate.due(t):
            return
        self._drop_removed()
        points = self._gripper_contacts()
        gripped = set()
        for obj, by_link in points.items():
            if not is_grip([p[0] for p in by_link.values()], self.min_angle):
                continue
            gripped.add(obj)
            n = self.counts[obj] = min(self.counts.get(obj, 0) + 1, self.max_grip_count)
            if n <= self.threshold:
                continue
            touching = {}
            for ln in by_link:
                arm = self.link_arm[ln]
                touching[arm] = touching.get(arm, 0) + 1
            if any(arm.held is not None for arm in touching):
                continue
            arm = max(touching, key=lambda a: touching[a])     # most links on the object
            self._attach(arm, obj, {ln: (p[1], p[2]) for ln, p in by_link.items() if ln in arm.links})
        for obj in list(self.counts):
            if obj in gripped:
                continue
            if self.counts[obj] > 0:
                self.counts[obj] -= 1
            arm = self._holder(obj)
            if arm is None or self.counts[obj] > self.threshold:
                continue
            if self._moved_off(arm, obj):
                self._detach(arm, "the gripper let go")
                self.counts[obj] = 0

    def _gripper_contacts(self):
        """{object (model, link): {gripper link: (mean force on the object, mean contact point and
        object position in the gripper link's frame)}} from the last step's contacts."""
        me = self.model.name
        acc = {}
        for c in self.world.contacts():
            if c.model1 == me and c.link1 in self.link_arm:
                glink, obj, f = c.link1, (c.model2, c.link2), c.force2
            elif c.model2 == me and c.link2 in self.link_arm:
                glink, obj, f = c.link2, (c.model1, c.link1), c.force1
            else:
                continue
            if obj[0] == me and obj[1] in self.link_arm:
                continue                      # finger on finger
            link = self._link(obj)
            if link is None or link.body is None:
                continue                      # static: never grasped
            a = acc.setdefault(obj, {}).setdefault(glink, [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0])
            for k in range(3):
                a[0][k] += f[k]
                a[1][k] += c.position[k]
            a[2] += 1
        out = {}
        for obj, by_link in acc.items():
            opos = self._link(obj).pose[0]
            for glink, (f, p, n) in by_link.items():
                pose = self.model.links[glink].pose
                mean = (p[0] / n, p[1] / n, p[2] / n)
                out.setdefault(obj, {})[glink] = ((f[0] / n, f[1] / n, f[2] / n), _in_frame(pose, mean),
                                                  _in_frame(pose, opos))
        return out

    def _moved_off(self, arm, obj):
        """Whether a gripping link's original contact point has moved off the object by more than
        release_tolerance (the distance from it to the object's origin has changed)."""
        olink = self._link(obj)
        for ln, (contact, opos) in arm.grip_points.items():
            pose = self.model.links[ln].pose
            now = quat_rotate(pose[1], contact)
            now = (now[0] + pose[0][0], now[1] + pose[0][1], now[2] + pose[0][2])
            if abs(_norm(_sub(contact, opos)) - _norm(_sub(now, olink.pose[0]))) > self.release_tolerance:
                return True
        return False

    # ---- attach / detach ------------------------------------------------------------------------
    def _link(self, obj):
        m = self.world.models.get(obj[0])
        return m.links.get(obj[1]) if m is not None and not m.removed else None

    def _holder(self, obj):
        for arm in self.arms:
            if arm.held == obj:
                return arm
        return None

    def _attach(self, arm, obj, grip_points):
        link = self._link(obj)
        arm.weld = self.world.weld(link, arm.palm)
        arm.held = obj
        arm.grip_points = grip_points
        if self.disable_collisions:
            link.set_collides(False)
        LOG.info("%s: attached %s::%s to gripper '%s' (palm link '%s')", self.name, obj[0], obj[1], arm.name,
                 arm.palm.name)

    def _detach(self, arm, why):
        obj = arm.held
        if arm.weld is not None:
            arm.weld.release()
        link = self._link(obj)
        if self.disable_collisions and link is not None:
            link.set_collides(True)
        arm.weld, arm.held, arm.grip_points = None, None, {}
        LOG.info("%s: released %s::%s from gripper '%s' (%s)", self.name, obj[0], obj[1], arm.name, why)

    def _drop_removed(self):
        for arm in self.arms:
            if arm.held is not None and self._link(arm.held) is None:
                self._detach(arm, "its model was deleted")
        self.counts = {o: n for o, n in self.counts.items() if self._link(o) is not None}

    @property
    def attached(self):
        """{arm name: (model, link)} of what the arms hold."""
        return {a.name: a.held for a in self.arms if a.held is not None}

    def reset(self):
        for arm in self.arms:
            if arm.held is not None:
                self._detach(arm, "the world was reset")
        self.counts = {}
        self.gate.reset()

    def shutdown(self):
        for arm in self.arms:
            if arm.held is not None:
                self._detach(arm, "the plugin was unloaded")


register_plugin(FILENAME, GraspFix)
