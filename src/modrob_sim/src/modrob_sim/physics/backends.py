"""The two ways a World steps, behind one interface: :class:`NativeBackend` (the C hot loop of
``native/modrob_ode_native.c``: collision, contact joints, quickStep and the guard's velocity
scan in C) and :class:`PureBackend` (the same semantics in Python with PyODE callbacks; triangle
meshes collide as their bounding boxes). The World picks one at construction and calls it for
everything that differs; nothing else in the World knows which one runs.

Interface. A backend is made with the World's ``WorldParts`` (world.py: its ODE world, spaces,
tables, caches and step settings, which the World keeps current) and keeps no reference to the
World itself, so the World's finalizer can tear the ODE objects down through the backend; it uses
only the physics-side interface of Model, Link and Joint (model.py):

    native                          True for the C loop
    set_seed(seed)                  ODE's random seed (quickStep's row order) after a reset
    register_geom(info)             a new geom of a model (info: the World's _GeomInfo)
    update_geom(info)               its collision bits / self_collide changed
    forget_model(entry)             the model (the World's entry for it) left the World
    remove_geom(geom)               free one geom (model removal and teardown)
    rebuild(models)                 the set of models, joints or the time step changed
    settings_changed()              the step settings of the parts (gravity, physics parameters
                                    and what follows from them) changed
    make_mesh_geom(mesh, dynamic, what) -> (geom, pose of the geom in the mesh frame)
    apply_damping()                 explicit joint damping for this step
    step(dt) -> contacts            collide + contact joints + quickStep (or dWorldStep); the
                                    native one also runs the guard's velocity scan here
    run(n, t, iterations, before_due, after_due, efforts) -> Stretch or None
                                    up to n steps natively (the pure backend: None, never);
                                    the first applies ``efforts`` (the World's queued efforts
                                    taken for the step: the joints' and the values) after the
                                    model actuators, as the World's step in Python does
    find_blowups() -> [(model, group, reason)]   the guard's scan after a step
    snapshot_iteration -> int       the iteration of the guard's last snapshot taken natively (-1:
                                    none since the last rebuild or drop_snapshot(); the pure: -1)
    snapshot_readers() -> (body, joint)   functions giving a body's (p, q, v, w) and a joint's
                                    (turns, last_raw) in that snapshot, for Model.capture_state
    drop_snapshot()                 forget it (the world was reset)
    contacts() -> [(info1, info2, pos, normal, depth, wrenches)]   the last step's contact points;
                                    wrenches = (f1, t1, f2, t2): ODE's feedback of the contact joint
    overlaps(model) -> {(m1, l1, m2, l2): depth}   spawn-overlap check
    new_watch(infos) -> handle      a contact watch on these geoms (the World's _GeomInfo of links
                                    of one model): from now on every step notes, where it makes
                                    its contacts, each pair of a watched geom with a geom on a
                                    body it made contacts with, and counts the steps
    drain_watch(handle) -> [(info watched, info other, steps)]   those pairs since the last
                                    drain, in the order first seen, with the number of steps in
                                    which each made contacts; then forgotten. A removed geom
                                    leaves every watch and every pair (remove_geom)
    close_watch(handle)             the watch ends (its handle may be given to a new one)
    close()                         free the backend's own objects
    new_actuator(joint, kind) -> record       an actuator's data (actuators.py)
    actuators_changed(actuators)    the World's list of actuators changed
    apply_actuators(actuators, t, dt)   every actuator's effort for the step starting at t
    track_turns(joints)             after a step: the turn counts of these joints
    new_model_actuator(model, kind) -> record   a model actuator's data (actuators.py)
    model_actuators_changed(actuators)   the World's list of model actuators changed
    apply_model_actuators(actuators)     every model actuator, before the joint actuators
    actuator_gains(r), set_actuator_gains(r, g), reset_actuator_pid(r), actuator_pid_state(r),
    actuator_terms(r), set_actuator_coeffs(r, coeffs)   an actuator's PID and segment
    set_actuator_queue(r, pieces)   the pieces queued behind a SEGMENT_PID actuator's own
                                    (actuators.Actuator.queue_pieces: the records' tuples)
    set_actuator_bodies(r, bodies)  the bodies an OUT_POSITION actuator turns with its joint
    set_actuator_master(r, joint)   the joint a FOLLOW_PID actuator follows (None: none)
    actuator_tracking_error(r, joint, t) -> (error, error_dot)   a SEGMENT_PID actuator's errors
                                    at t from the joint's state now, as its step at t computes them
                                    (the native stretches end before a step at which they leave
                                    its band: Actuator.watch_band)
"""
import ctypes
import math
from collections import OrderedDict

import ode

from ..errors import SimulationError
from . import actuators as act
from . import meshes as meshlib
from . import native as native_mod
from . import odelib
from .model import FORCE_CAP, MIMIC_COUPLING_FORCE, MIMIC_GAIN
from .transforms import IDENTITY_POSE, dot
from .world_parts import may_sleep, warn_once

_APPROX1 = ode.ContactApprox1_1 | ode.ContactApprox1_2
_BASE_MODE = _APPROX1 | ode.ContactSoftERP | ode.ContactSoftCFM
ZERO3 = (0.0, 0.0, 0.0)


class _PairParams(object):
    __slots__ = ("mu", "mu2", "erp", "cfm", "mode", "shift", "cap", "isotropic", "fdir_side", "fdir",
                 "max_contacts")


def velocity_reason(b, vmax2, wmax2):
    """Why a body's velocity trips the guard (NaN, linear or angular runaway)."""
    v = b.getLinearVel()
    w = b.getAngularVel()
    v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    if not (math.isfinite(v2) and math.isfinite(w2)):
        return "non-finite velocity (NaN/inf)"
    if not v2 < vmax2:
        return "runaway linear velocity %.3g m/s (limit %.3g)" % (math.sqrt(v2), math.sqrt(vmax2))
    return "runaway angular velocity %.3g rad/s (limit %.3g)" % (math.sqrt(w2), math.sqrt(wmax2))


def contact_explosion(model, n, cmax):
    return (model, model.dynamic_groups[0],
            "contact explosion: %d contacts in one step (limit %d)" % (n, cmax))


class MrTurn(ctypes.Structure):
    """native/modrob_ode_native.c's MrTurn: a joint's whole turns (Joint.turn_record)."""
    _fields_ = [("joint", ctypes.c_void_p), ("last_raw", ctypes.c_double), ("turns", ctypes.c_longlong)]


class MrPiece(ctypes.Structure):
    """native/modrob_ode_native.c's MrPiece: a trajectory piece queued behind a SEGMENT_PID
    actuator's own (Actuator.queue_pieces; the actuator's fields of the same names)."""
    _fields_ = [("traj_kind", ctypes.c_int), ("ncoef", ctypes.c_int), ("has_offset", ctypes.c_int),
                ("coef", ctypes.c_double * act.MAX_COEFFS)] + \
        [(n, ctypes.c_double) for n in ("seg_t0", "seg_t1", "rel_base", "offset", "abs_until", "rel_until")]


class MrActuator(ctypes.Structure):
    """native/modrob_ode_native.c's MrActuator: one actuator's data (actuators.PyRecord's fields
    and its PID's, flat)."""
    _fields_ = [("joint", ctypes.c_void_p), ("turn", ctypes.POINTER(MrTurn))] + \
        [(n, ctypes.c_int)
         for n in ("slider", "kind", "err_kind", "has_hw_limit", "antiwindup", "has_extra")] + \
        [(n, ctypes.c_double) for n in (
            "lower", "upper", "hw_limit", "joint_limit", "force_cap", "command", "extra",
            "p", "i", "d", "i_max", "i_min",
            "p_error_last", "p_error", "i_error", "d_error", "cmd", "p_term", "i_term", "d_term",
            "t", "position", "velocity", "set_point", "desired_velocity", "out", "applied")] + \
        [("traj_kind", ctypes.c_int), ("ncoef", ctypes.c_int), ("has_offset", ctypes.c_int),
         ("coef", ctypes.c_double * act.MAX_COEFFS)] + \
        [(n, ctypes.c_double) for n in ("seg_t0", "seg_t1", "rel_base", "offset", "ff", "abs_until",
                                        "rel_until", "max_force", "accel", "motor_vel")] + \
        [("out_kind", ctypes.c_int), ("vel_limit", ctypes.c_double), ("nbodies", ctypes.c_int),
         ("bodies", ctypes.c_void_p), ("pos_prev", ctypes.c_double), ("watch", ctypes.c_int)] + \
        [(n, ctypes.c_double)
         for n in ("watch_target", "watch_tol", "watch_vel", "watch_timeout", "moved_at")] + \
        [("master", ctypes.c_void_p), ("master_turn", ctypes.POINTER(MrTurn)),
         ("master_slider", ctypes.c_int)] + \
        [(n, ctypes.c_double) for n in ("mult", "follow_offset", "deadband")] + \
        [("has_follow_vel", ctypes.c_int)] + \
        [(n, ctypes.c_double) for n in ("follow_vel", "bias", "master_position")] + \
        [("band", ctypes.c_int), ("band_pos", ctypes.c_double), ("band_vel", ctypes.c_double),
         ("nqueue", ctypes.c_int), ("qnext", ctypes.c_int), ("queue", MrPiece * act.MAX_QUEUE)]


class MrModelActuator(ctypes.Structure):
    """native/modrob_ode_native.c's MrModelActuator: one model actuator (actuators.PyModelRecord's
    command fields, the model's bodies and its canonical link's frame)."""
    _fields_ = [("kind", ctypes.c_int), ("nbodies", ctypes.c_int), ("base", ctypes.c_void_p),
                ("bodies", ctypes.POINTER(ctypes.c_void_p)), ("T", ctypes.c_double * 7)] + \
        [(n, ctypes.c_double) for n in ("vx", "vy", "wz")]


class _Mimic(ctypes.Structure):
    """MrStretchMimic: a mimic joint (Joint.drive_mimic) and its master."""
    _fields_ = [("joint", ctypes.c_void_p), ("master", ctypes.c_void_p), ("turn", ctypes.POINTER(MrTurn)),
                ("master_turn", ctypes.POINTER(MrTurn))] + \
        [(n, ctypes.c_int) for n in ("slider", "master_slider", "has_lower", "has_upper")] + \
        [(n, ctypes.c_double) for n in ("mult", "offset", "lower", "upper", "child_inertia")]


class _Soft(ctypes.Structure):
    """MrStretchSoft: a revolute joint with limits beyond +-pi (Joint.update_soft_limits)."""
    _fields_ = [("joint", ctypes.c_void_p), ("turn", ctypes.POINTER(MrTurn)), ("lower", ctypes.c_double),
                ("upper", ctypes.c_double)]


class _Stretch(ctypes.Structure):
    """MrStretch: the settings and results of mr_run_steps."""
    _fields_ = [("acts", ctypes.c_void_p), ("nacts", ctypes.c_int), ("ndamp", ctypes.c_int),
                ("damp_joints", ctypes.c_void_p), ("damp_kinds", ctypes.c_void_p),
                ("damp_coef", ctypes.c_void_p), ("bodies", ctypes.c_void_p), ("nbodies", ctypes.c_int),
                ("nturns", ctypes.c_int), ("turns", ctypes.c_void_p),
                ("guard_max_contacts", ctypes.c_int), ("max_contacts", ctypes.c_int),
                ("snapshot_interval", ctypes.c_int)] + \
        [(n, ctypes.c_double)
         for n in ("vmax2", "wmax2", "dt", "gx", "gy", "gz", "layer", "time", "last_start")] + \
        [("iterations", ctypes.c_longlong), ("before_due", ctypes.c_double), ("after_due", ctypes.c_double),
         ("wake", ctypes.c_void_p), ("observer", ctypes.c_void_p), ("observer_user", ctypes.c_void_p),
         ("ncontacts", ctypes.c_int), ("guard", ctypes.c_int), ("world_step", ctypes.c_int),
         ("first_bad", ctypes.c_int), ("after", ctypes.c_int),
         ("nmimic", ctypes.c_int), ("mimics", ctypes.POINTER(_Mimic)), ("nsoft", ctypes.c_int),
         ("softs", ctypes.POINTER(_Soft))] + \
        [(n, ctypes.c_int) for n in ("param_vel", "param_fmax", "param_lo_stop", "param_hi_stop")] + \
        [("mimic_gain", ctypes.c_double), ("mimic_force", ctypes.c_double),
         ("macts", ctypes.c_void_p), ("nmacts", ctypes.c_int),
         ("snap", ctypes.c_void_p), ("snap_turns", ctypes.c_void_p), ("snap_iter", ctypes.c_longlong),
         ("nefforts", ctypes.c_int), ("effort_joints", ctypes.c_void_p), ("effort_kinds", ctypes.c_void_p),
         ("effort_values", ctypes.c_void_p)]


#: doubles per body in the C loop's guard snapshot (MR_SNAP_BODY)
SNAP_BODY = 13


class Stretch(object):
    """What a native stretch did: ``steps`` made, the ``time`` and ``iterations`` after them,
    ``after`` (the last step's after-hooks are due), ``guard`` (the guard must look at the last
    step), ``ncontacts`` of the last step."""
    __slots__ = ("steps", "time", "iterations", "after", "guard", "ncontacts")


class PureBackend(object):
    native = False

    def __init__(self, parts):
        self.p = parts
        self.seed = 0
        self.ncontacts = 0
        self.contact_log = []
        self.joints = []      # this step's contact joints, as contact_log (until the feedback is read)
        self.feedback = []    # their feedback after the step: (f1, t1, f2, t2) as contact_log
        self.made = []        # (contact, body1, body2, whole depth) of this step's contact joints
        self.capped = False   # a contact of this step had its correction capped at maxVel
        self.anchors = {}     # the contacts' anchors by pair (_anchor): the last step's, matched now
        self._anchors_next = {}
        self.watches = {}     # contact watch handle -> (its infos, {(info, other info): steps} seen)
        self.watched = {}     # geom -> the seen dicts of the watches that hold it
        self._next_watch = 0

    # ---- actuators (actuators.step_python) ----------------------------------------------------
    @staticmethod
    def new_actuator(joint, kind):
        return act.PyRecord(kind)

    def actuators_changed(self, actuators):
        pass

    @staticmethod
    def apply_actuators(actuators, t, dt):
        act.apply_python([(a.record, a.joint) for a in actuators], t, dt)

    @staticmethod
    def new_model_actuator(model, kind):
        return act.PyModelRecord(kind)

    def model_actuators_changed(self, actuators):
        pass

    @staticmethod
    def apply_model_actuators(actuators):
        for a in actuators:
            act.step_model_python(a.record, a.model)

    @staticmethod
    def track_turns(joints):
        for j in joints:
            j.track_turns()

    @staticmethod
    def actuator_gains(r):
        return r.pid.gains

    @staticmethod
    def set_actuator_gains(r, gains):
        r.pid.set_gains(gains)

    @staticmethod
    def reset_actuator_pid(r):
        r.pid.reset()

    @staticmethod
    def actuator_pid_state(r):
        return r.pid.state()

    @staticmethod
    def actuator_terms(r):
        p = r.pid
        return (p.p_error, p.d_error) + tuple(p.terms)

    @staticmethod
    def set_actuator_coeffs(r, coeffs):
        r.coef = [float(c) for c in coeffs]

    @staticmethod
    def set_actuator_bodies(r, bodies):
        r.bodies = tuple(bodies)

    @staticmethod
    def set_actuator_master(r, joint):
        r.master = joint

    @staticmethod
    def set_actuator_queue(r, pieces):
        r.queue = list(pieces)
        r.qnext = 0

    @staticmethod
    def actuator_tracking_error(r, joint, t):
        act.piece_at(r, t)
        dpos, dvel = act.segment_sample(r, t)
        return act.tracking_error(r.err_kind, dpos, dvel, joint.position, joint.velocity)

    def set_seed(self, seed):
        self.seed = seed

    def register_geom(self, info):
        pass

    def update_geom(self, info):
        pass

    def forget_model(self, entry):
        self.forget_anchors()   # they hold its geoms

    def remove_geom(self, geom):
        if self.watches:
            self._unwatch_geom(geom)

    def rebuild(self, models):
        pass

    def settings_changed(self):
        pass

    # ---- contact watches (noted in _near) -----------------------------------------------------
    def new_watch(self, infos):
        handle = self._next_watch
        self._next_watch += 1
        seen = OrderedDict()
        self.watches[handle] = (list(infos), seen)
        for i in infos:
            self.watched.setdefault(i.geom, []).append(seen)
        return handle

    def drain_watch(self, handle):
        w = self.watches.get(handle)
        if w is None:
            return []
        out = [(mine, other, steps) for (mine, other), steps in w[1].items()]
        w[1].clear()
        return out

    def close_watch(self, handle):
        w = self.watches.pop(handle, None)
        if w is None:
            return
        for i in w[0]:
            rest = [seen for seen in self.watched.get(i.geom, ()) if seen is not w[1]]
            if rest:
                self.watched[i.geom] = rest
            else:
                self.watched.pop(i.geom, None)

    def _unwatch_geom(self, geom):
        """``geom`` leaves the world: no watch holds it or a pair with it any more."""
        self.watched.pop(geom, None)
        for infos, seen in self.watches.values():
            infos[:] = [i for i in infos if i.geom is not geom]
            for key in [k for k in seen if k[0].geom is geom or k[1].geom is geom]:
                del seen[key]

    def wake(self):
        pass

    def clear_wake(self):
        pass

    def set_observer(self, fn, user):
        pass

    @staticmethod
    def run(n, t, iterations, before_due, after_due, efforts):
        """No native stretches on the pure-Python path: every step is World._step_once."""
        return None

    #: every guard snapshot of the pure-Python path is the World's own
    snapshot_iteration = -1

    def drop_snapshot(self):
        pass

    def forget_anchors(self):
        """The contacts' anchors go (the bodies were put elsewhere)."""
        self.anchors, self._anchors_next = {}, {}

    def close(self):
        # the last step's contacts and the watches hold bodies, geoms and contact joints: not past
        # the World's end
        self.contact_log, self.made, self.joints, self.feedback = [], [], [], []
        self.watches, self.watched = {}, {}
        self.forget_anchors()

    def make_mesh_geom(self, mesh, dynamic, what):
        warn_once(self.p.warned, "mesh-as-box", "%s: triangle meshes collide as their bounding boxes on "
                  "the pure-Python path (%s)" % (what, native_mod.REASON or "native loop off for this World"))
        verts, _tris = mesh
        lo, hi = meshlib.bounds(verts)
        size = tuple(max(b - a, 1e-4) for a, b in zip(lo, hi))
        center = tuple(0.5 * (a + b) for a, b in zip(lo, hi))
        space = self.p.dyn_space if dynamic else self.p.static_space
        return ode.GeomBox(space, lengths=size), (center, (0.0, 0.0, 0.0, 1.0))

    def apply_damping(self):
        for j, coefficient in self.p.damped:
            j.add_damping(coefficient)

    def step(self, dt):
        world = self.p
        world.contact_group.empty()
        self.ncontacts = 0
        self.contact_log = []
        self.joints = []
        self.made = []
        self.capped = False
        self.anchors, self._anchors_next = self._anchors_next, {}
        self._collide(world)
        seed0 = self.seed
        odelib.set_seed(seed0)
        if world.world_step:
            world.ode_world.step(dt)
        elif self.capped:
            self._split_solve(world, dt, seed0)
        else:
            world.ode_world.quickStep(dt)
        self.seed = odelib.get_seed()
        self._read_feedback()
        self._wake_held(world)
        return self.ncontacts

    def _split_solve(self, world, dt, seed0):
        """As the C loop's mr_split_solve (Gazebo's split of contact correction): pass 1 with
        the capped contacts gives the velocities, pass 2 from the same state with the whole
        depths gives the positions."""
        bodies = [g.body for m in world.dynamic_models for g in m.dynamic_groups]
        saved = [(b.getPosition(), b.getQuaternion(), b.getLinearVel(), b.getAngularVel(),
                  b.getForce(), b.getTorque()) for b in bodies]
        world.ode_world.quickStep(dt)
        velocities = [(b.getLinearVel(), b.getAngularVel()) for b in bodies]
        for b, (p, q, v, w, f, t) in zip(bodies, saved):
            b.setPosition(p)
            b.setQuaternion(q)
            b.setLinearVel(v)
            b.setAngularVel(w)
            b.setForce(f)
            b.setTorque(t)
        for j in self.joints:
            j.setFeedback(False)   # while the joint exists (see _read_feedback)
        world.contact_group.empty()
        self.joints = []
        for c, b1, b2, depth in self.made:
            pos, normal, _d, g1, g2 = c.getContactGeomParams()
            c.setContactGeomParams(pos, normal, depth, g1, g2)
            j = ode.ContactJoint(world.ode_world, world.contact_group, c)
            j.attach(b1, b2)
            j.setFeedback(True)
            self.joints.append(j)
        odelib.set_seed(seed0)
        world.ode_world.quickStep(dt)
        for b, (v, w) in zip(bodies, velocities):
            b.setLinearVel(v)
            b.setAngularVel(w)

    def _wake_held(self, world):
        """As the C loop's mr_wake_held: a body that may sleep, touching an awake body that never
        does (a robot's link), has its idle count reset after the step (enable())."""
        for i1, i2, _p, _n, _d in self.contact_log:
            b1, b2 = i1.body, i2.body
            if b1 is None or b2 is None:
                continue
            if may_sleep(i1.model, world.params):
                if b2.isEnabled() and not may_sleep(i2.model, world.params):
                    b1.enable()
            elif may_sleep(i2.model, world.params) and b1.isEnabled():
                b2.enable()

    def find_blowups(self):
        world = self.p
        vmax2, wmax2 = world.vmax2, world.wmax2
        cmax = world.params["guard_max_contacts"]
        flagged = []
        entries = world.entries
        for m in world.dynamic_models:
            bad = None
            e = entries[m]
            for g in m.dynamic_groups:
                b = g.body
                v = b.getLinearVel()
                w = b.getAngularVel()
                v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
                w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
                if not (v2 < vmax2 and w2 < wmax2):
                    bad = (m, g, velocity_reason(b, vmax2, wmax2))
                    break
            if bad is None and e.ncontacts > cmax:
                bad = contact_explosion(m, e.ncontacts, cmax)
            e.ncontacts = 0
            if bad is not None:
                flagged.append(bad)
        return flagged

    def contacts(self):
        return [(i1, i2, tuple(pos), tuple(normal), depth, w)
                for (i1, i2, pos, normal, depth), w in zip(self.contact_log, self.feedback)]

    def _read_feedback(self):
        """The contact joints' feedback, read at once and then turned off: the World may empty
        their group (a model removed, a reset) before anyone asks, and PyODE (which unsets a
        joint's feedback when it frees the Python object) aborts on a joint already destroyed."""
        out = []
        for (i1, i2, _p, _n, _d), j in zip(self.contact_log, self.joints):
            f1, t1, f2, t2 = j.getFeedback()
            j.setFeedback(False)
            if i1.body is None:
                # attached as (None, b2): ODE makes the one body its first, so its force is f1
                f1, t1, f2, t2 = ZERO3, ZERO3, f1, t1
            elif i2.body is None:
                f2 = t2 = ZERO3
            out.append((f1, t1, f2, t2))
        self.feedback = out
        self.joints = []

    def overlaps(self, model):
        world = self.p
        found = {}

        def cb(_arg, g1, g2):
            i1, i2 = world.geom_info.get(g1), world.geom_info.get(g2)
            if i1 is None or i2 is None or i1.model is i2.model:
                return
            if i1.body is None and i2.body is None:
                return
            for c in ode.collide(g1, g2):
                d = c.getContactGeomParams()[2]
                key = (i1.model.name, i1.link.name, i2.model.name, i2.link.name)
                if d > found.get(key, 0.0):
                    found[key] = d

        for geom in model.geoms:
            if isinstance(geom, ode.GeomPlane):
                continue
            for sp in (world.static_space, world.dyn_space):
                ode.collide2(geom, sp, None, cb)
        return found

    # ---- collision (PyODE near callbacks) ---------------------------------------------------
    def _collide(self, w):
        w.dyn_space.collide(w, self._near)
        ode.collide2(w.static_space, w.dyn_space, w, self._near_top)

    def _near_top(self, w, g1, g2):
        if g1.isSpace() or g2.isSpace():
            ode.collide2(g1, g2, w, self._near)
        else:
            self._near(w, g1, g2)

    def _pair(self, w, s1, s2, static1, static2):
        """Contact parameters of a surface pair, as Gazebo: kp in series, kd summed, the smaller
        mu; maxVel and minDepth are per BODY in Gazebo (the smaller of the two bodies'), so a
        static side does not count, and minDepth replaces the world's contact_surface_layer (a
        surface without minDepth takes the layer);
        with <fdir1> on both sides, that of the smaller mu1; the world's cap of contacts lowered
        by either side's own."""
        key = (s1, s2, static1, static2)
        pp = w.pair_cache.get(key)
        if pp is not None:
            return pp
        dt = w.dt
        kp = 1.0 / (1.0 / s1.kp + 1.0 / s2.kp)
        kd = s1.kd + s2.kd
        pp = _PairParams()
        pp.erp = dt * kp / (dt * kp + kd)
        pp.cfm = 1.0 / (dt * kp + kd)
        pp.mu = min(s1.mu1, s2.mu1)
        pp.mu2 = min(s1.mu2, s2.mu2)
        pp.isotropic = pp.mu == pp.mu2
        pp.mode = _BASE_MODE | (0 if pp.isotropic else ode.ContactMu2)
        use2 = any(s2.fdir1) and (not any(s1.fdir1) or s1.mu1 > s2.mu1)
        pp.fdir_side = 2 if use2 else (1 if any(s1.fdir1) else 0)
        pp.fdir = s2.fdir1 if use2 else s1.fdir1
        pp.max_contacts = min([w.max_contacts] + [s.max_contacts for s in (s1, s2) if s.max_contacts > 0])
        sides = [s for s, st in ((s1, static1), (s2, static2)) if not st] or [s1, s2]
        layer = w.params["contact_surface_layer"]
        pp.shift = min(layer if s.min_depth is None else s.min_depth for s in sides)
        max_vel = min(s.max_vel for s in sides)
        pp.cap = max_vel * dt / pp.erp if pp.erp > 0 else float("inf")
        w.pair_cache[key] = pp
        return pp

    def _near(self, w, g1, g2):
        info = w.geom_info
        i1 = info.get(g1)
        i2 = info.get(g2)
        if i1 is None or i2 is None or not (g1.isEnabled() and g2.isEnabled()):
            return   # (a disabled geom: Link.set_collides; space-against-space collision passes them)
        m = i1.model
        if m is i2.model:
            if not (i1.self_collide or i2.self_collide) or i1.group == i2.group or \
                    (i1.group, i2.group) in i1.entry.adjacent:
                return
        b1, b2 = i1.body, i2.body
        if (b1 is None or not b1.isEnabled()) and (b2 is None or not b2.isEnabled()):
            return
        contacts = ode.collide(g1, g2)
        if not contacts:
            return
        n = len(contacts)
        pp = self._pair(w, i1.surface, i2.surface, b1 is None, b2 is None)
        cap = pp.max_contacts
        if n > cap:
            contacts = _select_spread(contacts, cap)
            n = cap
        self.ncontacts += n
        i1.entry.ncontacts += n
        i2.entry.ncontacts += n
        watched = self.watched
        if watched:
            # the contact watches: a watched geom's pair with a geom on a body (a pair of geoms
            # comes here at most once per step: one more step for it)
            if b2 is not None:
                for seen in watched.get(g1, ()):
                    seen[(i1, i2)] = seen.get((i1, i2), 0) + 1
            if b1 is not None:
                for seen in watched.get(g2, ()):
                    seen[(i2, i1)] = seen.get((i2, i1), 0) + 1
        fdir = None
        world = w.ode_world
        group = w.contact_group
        for k, c in enumerate(contacts):
            pos, normal, depth, _a, _b = c.getContactGeomParams()
            if k == 0 and (pp.fdir_side or pp.isotropic):
                if pp.fdir_side:
                    fdir = _given_fdir(g1 if pp.fdir_side == 1 else g2, pp.fdir)
                else:
                    fdir = _friction_dir(w.gravity, b1, b2, pos, normal)
            mode = pp.mode
            f = None if fdir is None else _contact_fdir(fdir, pp.fdir_side, normal)
            if f is not None:
                mode |= ode.ContactFDir1
            whole = depth - pp.shift
            if whole < 0.0:
                whole = 0.0
            d = whole
            if d > pp.cap:
                d = pp.cap
                self.capped = True
            if d != depth:
                c.setContactGeomParams(pos, normal, d, g1, g2)
            c.setMode(mode)
            c.setMu(pp.mu)
            c.setMu2(pp.mu2)
            c.setSoftERP(pp.erp)
            c.setSoftCFM(pp.cfm)
            if f is not None:
                c.setFDir1(f)
            if pp.fdir_side == 0:
                self._anchor(g1, g2, b1, b2, c, pos, normal, mode, pp.erp, w.dt)
            j = ode.ContactJoint(world, group, c)
            j.attach(b1, b2)
            j.setFeedback(True)
            self.made.append((c, b1, b2, whole))
            self.contact_log.append((i1, i2, pos, normal, depth))
            self.joints.append(j)

    def _anchor(self, g1, g2, b1, b2, c, pos, n, mode, erp, dt):
        """Static friction anchors, the C loop's mr_anchor (the same rule; the reason is there): a
        contact takes the last step's anchor of the same pair whose points are nearest to it
        (both within ANCHOR_RADIUS of it across the contact plane, and of each other), and its
        first friction row, along the gap, asks for the velocity that closes it in one step at its
        ERP; without one it is anchored where it is. Only between two moving bodies."""
        if b1 is None or b2 is None:
            return
        r2 = ANCHOR_RADIUS * ANCHOR_RADIUS
        best, found = r2, None
        last = self.anchors.get((g1, g2))
        if last is None:
            last = [(a2, a1) for a1, a2 in self.anchors.get((g2, g1), ())]
        for a1, a2 in last:
            w1, w2 = _to_world(b1, a1), _to_world(b2, a2)
            t1, t2 = _across2(w1, pos, n), _across2(w2, pos, n)
            if t1 < best and t2 < best and _across2(w1, w2, n) < r2:
                best, found = max(t1, t2), (a1, a2)
        mine = self._anchors_next.setdefault((g1, g2), [])
        if found is None:
            mine.append((_to_body(b1, pos), _to_body(b2, pos)))
            return
        mine.append(found)
        w1, w2 = _to_world(b1, found[0]), _to_world(b2, found[1])
        sgn = 1.0 if b1 is not None else -1.0   # ODE's body 0 (b2 when b1 is static)
        e = [sgn * (x - y) for x, y in zip(w1, w2)]
        en = e[0] * n[0] + e[1] * n[1] + e[2] * n[2]
        e = [x - en * y for x, y in zip(e, n)]
        length = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
        if not length > 1e-12:
            return
        c.setFDir1((e[0] / length, e[1] / length, e[2] / length))
        c.setMode(mode | ode.ContactFDir1 | ode.ContactMotion1)
        c.setMotion1(-erp * length / dt)


ANCHOR_RADIUS = 1e-3   # m: the C loop's MR_ANCHOR_RADIUS


def _to_body(b, p):
    return tuple(p) if b is None else b.getPosRelPoint(p)


def _to_world(b, a):
    return tuple(a) if b is None else b.getRelPointPos(a)


def _across2(a, b, n):
    """The squared distance of two points across the plane of normal ``n``."""
    d = (a[0] - b[0], a[1] - b[1], a[2] - b[2])
    dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2]
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - dn * dn


def _friction_dir(g, b1, b2, pos, n):
    """First friction direction for an isotropic pyramid: along the relative sliding velocity,
    or (at rest) along gravity's tangential part, so that the pyramid's limit mu*N applies
    in the direction the contact would slip (ODE's arbitrary default lets a box hold on a
    slope steeper than atan(mu) by up to sqrt(2))."""
    vx = vy = vz = 0.0
    if b1 is not None:
        v = b1.getPointVel(pos)
        vx, vy, vz = v
    if b2 is not None:
        v = b2.getPointVel(pos)
        vx -= v[0]
        vy -= v[1]
        vz -= v[2]
    vn = vx * n[0] + vy * n[1] + vz * n[2]
    tx, ty, tz = vx - vn * n[0], vy - vn * n[1], vz - vn * n[2]
    t2 = tx * tx + ty * ty + tz * tz
    if t2 < 1e-10:
        gn = g[0] * n[0] + g[1] * n[1] + g[2] * n[2]
        tx, ty, tz = g[0] - gn * n[0], g[1] - gn * n[1], g[2] - gn * n[2]
        t2 = tx * tx + ty * ty + tz * tz
        if t2 < 1e-12 * (dot(g, g) + 1e-30):
            return None
    s = 1.0 / math.sqrt(t2)
    return (tx * s, ty * s, tz * s)


def _select_spread(contacts, k):
    """k of the contacts: the deepest, then repeatedly the one farthest from those chosen (the
    same rule as the C loop), so that a resting face keeps a wide support."""
    pts = [c.getContactGeomParams() for c in contacts]
    n = len(pts)
    best = max(range(n), key=lambda i: pts[i][2])
    chosen = [best]
    p0 = pts[best][0]
    dmin = [(p[0][0] - p0[0]) ** 2 + (p[0][1] - p0[1]) ** 2 + (p[0][2] - p0[2]) ** 2 for p in pts]
    used = set(chosen)
    while len(chosen) < k:
        far = max((i for i in range(n) if i not in used), key=lambda i: dmin[i])
        chosen.append(far)
        used.add(far)
        pf = pts[far][0]
        for i in range(n):
            d = (pts[i][0][0] - pf[0]) ** 2 + (pts[i][0][1] - pf[1]) ** 2 + (pts[i][0][2] - pf[2]) ** 2
            if d < dmin[i]:
                dmin[i] = d
    return [contacts[i] for i in chosen]


def _given_fdir(geom, fdir):
    """<fdir1> (collision frame) in the world, unit length; None if it has none."""
    if isinstance(geom, ode.GeomPlane):  # not placeable: its fdir1 is in the world frame
        r = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    else:
        r = geom.getRotation()
    f = (r[0] * fdir[0] + r[1] * fdir[1] + r[2] * fdir[2],
         r[3] * fdir[0] + r[4] * fdir[1] + r[5] * fdir[2],
         r[6] * fdir[0] + r[7] * fdir[1] + r[8] * fdir[2])
    f2 = f[0] * f[0] + f[1] * f[1] + f[2] * f[2]
    if not f2 > 0:
        return None
    k = 1.0 / math.sqrt(f2)
    return (f[0] * k, f[1] * k, f[2] * k)


def _contact_fdir(f, given, n):
    """The first friction direction of one contact of a pair from the pair's (unit) direction
    ``f``, or None for ODE's own directions; the C loop's mr_contact_fdir, the same rule. Each
    contact against its OWN normal: one pair's contacts can face different ways (a mesh in a box
    touches several faces), and a first direction along a contact's normal makes a second normal
    row whose friction bound mu*N cancels the first, so the solver's impulses grow without bound
    (NaN, and ODE aborts the process). ``given`` (a surface's <fdir1>, Gazebo's rule): NOT
    projected on the contact plane (a wheel's fdir1 turns with it, and its first friction row
    leans into the normal as it rolls); ODE's own directions when parallel to the normal. Else
    (along the slip): projected on the contact's plane (unchanged where it lies in it)."""
    fn = f[0] * n[0] + f[1] * n[1] + f[2] * n[2]
    if given:
        c = (n[1] * f[2] - n[2] * f[1], n[2] * f[0] - n[0] * f[2], n[0] * f[1] - n[1] * f[0])
        return f if c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 1e-12 else None
    if abs(fn) <= 1e-9:
        return f
    t = (f[0] - fn * n[0], f[1] - fn * n[1], f[2] - fn * n[2])
    t2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2]
    if not t2 > 1e-12:
        return None
    k = 1.0 / math.sqrt(t2)
    return (t[0] * k, t[1] * k, t[2] * k)


def _declare_run(lib):
    f = lib.mr_run_steps
    f.restype = ctypes.c_int
    f.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Stretch), ctypes.c_int]
    return f


def geom_ptr(geom):
    """The dGeomID of a PyODE geom or a native mesh (for C code that takes geoms)."""
    return geom.ptr if isinstance(geom, NativeMesh) else geom._id()


class NativeBackend(object):
    """The C hot loop (ctypes, ``native.LIB``) on the World's PyODE world and spaces."""
    native = True

    def __init__(self, nat, parts):
        self.nat = nat
        self.p = parts
        self._run = _declare_run(nat)
        if ctypes.sizeof(MrActuator) != nat.mr_actuator_size():
            raise SimulationError(
                "%s's MrActuator is %d bytes, its ctypes mirror backends.MrActuator %d: the two declarations "
                "differ (a field added to one only); make them the same, then `make build`"
                % (getattr(nat, "_name", "the C library"), nat.mr_actuator_size(), ctypes.sizeof(MrActuator)))
        self._contact_vals = nat.mr_contact_vals()
        self.ctx = nat.mr_ctx_new(odelib.raw_pointer(parts.ode_world), parts.static_space._id(),
                                  parts.dyn_space._id())
        self._surface_index = {}
        self._model_slots = []
        self._next_uid = 1
        self._body_owner = []
        self._body_array = None
        self._damp_arrays = None
        self.ncontacts = 0
        self._first_bad = ctypes.c_int(-1)   # the guard scan of the last step (mr_step_checked)
        self._first_bad_ref = ctypes.byref(self._first_bad)
        self._turns = {}                     # Joint -> its MrTurn (kept while the joint counts turns)
        self._turn_array = (ctypes.POINTER(MrTurn) * 1)()
        self._nturns = 0
        self._acts = ()
        self._act_array = (ctypes.POINTER(MrActuator) * 1)()
        self._macts = ()
        self._macts_array = (ctypes.POINTER(MrModelActuator) * 1)()
        self._body_lists = {}               # MrActuator address -> its OUT_POSITION body array
        self._error_out = (ctypes.c_double * 2)()   # actuator_tracking_error's answer
        self._stretch = _Stretch()
        self._stretch_ref = ctypes.byref(self._stretch)
        self._wake = ctypes.c_int(0)        # World.wake, from any thread; mr_run_steps reads it
        self._stretch.wake = ctypes.addressof(self._wake)
        self._mimics = (_Mimic * 1)()
        self._softs = (_Soft * 1)()
        self.stretch_ok = True              # every mimic and soft-limit joint is one the C loop drives
        self._snap = self._snap_turns = None
        self._stretch.snap_iter = -1
        self._effort_joints = ()             # the joints of the last efforts handed to a stretch
        self._effort_arrays = None           # their (ODE joints, kinds, values) for mr_run_steps
        # what mr_run_steps reads besides each run's times and efforts is written into the stretch
        # where it changes (here, rebuild, settings_changed, the actuator lists), not at every run
        b = self._stretch
        b.param_vel, b.param_fmax = odelib.PARAM_VEL, odelib.PARAM_FMAX
        b.param_lo_stop, b.param_hi_stop = odelib.PARAM_LO_STOP, odelib.PARAM_HI_STOP
        b.mimic_gain, b.mimic_force = MIMIC_GAIN, MIMIC_COUPLING_FORCE
        b.acts = ctypes.addressof(self._act_array)
        b.macts = ctypes.addressof(self._macts_array)

    def set_seed(self, seed):
        self.nat.mr_set_seed(self.ctx, seed)

    # ---- actuators (mr_apply_actuators) -------------------------------------------------------
    def new_actuator(self, joint, kind):
        r = MrActuator()
        r.joint = odelib.raw_pointer(joint.ode_joint)
        r.slider = 0 if joint.is_angular else 1
        r.kind = kind
        lim = joint.effort_limit
        r.joint_limit = float(lim) if lim is not None and lim > 0.0 else 0.0
        r.force_cap = FORCE_CAP
        r.traj_kind = act.HOLD
        r.ncoef = 1
        r.abs_until = r.rel_until = act.INF
        r.out_kind = act.OUT_EFFORT
        r.vel_limit = act.INF
        self._bind_turn(r, joint)
        return r

    def _bind_turn(self, r, joint):
        rec = self._turns.get(joint)
        r.turn = ctypes.pointer(rec) if rec is not None else ctypes.POINTER(MrTurn)()

    def set_actuator_master(self, r, joint):
        if joint is None:
            r.master = None
            r.master_turn = ctypes.POINTER(MrTurn)()
            return
        r.master = odelib.raw_pointer(joint.ode_joint)
        r.master_slider = 0 if joint.is_angular else 1
        rec = self._turns.get(joint)
        r.master_turn = ctypes.pointer(rec) if rec is not None else ctypes.POINTER(MrTurn)()

    def actuators_changed(self, actuators):
        self._acts = tuple(actuators)
        live = {ctypes.addressof(a.record) for a in self._acts}
        self._body_lists = {k: v for k, v in self._body_lists.items() if k in live}
        arr = (ctypes.POINTER(MrActuator) * max(1, len(self._acts)))()
        for k, a in enumerate(self._acts):
            arr[k] = ctypes.pointer(a.record)
        self._act_array = arr
        self._stretch.acts, self._stretch.nacts = ctypes.addressof(arr), len(self._acts)

    def apply_actuators(self, actuators, t, dt):
        if actuators:
            self.nat.mr_apply_actuators(self._act_array, len(self._acts), t, dt, odelib.PARAM_VEL,
                                        odelib.PARAM_FMAX)

    # ---- model actuators (mr_apply_model_actuators) -------------------------------------------
    def new_model_actuator(self, model, kind):
        r = MrModelActuator()
        base = model.canonical_link
        bodies = model.bodies
        r.kind = kind
        r.base = odelib.raw_pointer(base.body)
        r.nbodies = len(bodies)
        r.keepalive = (ctypes.c_void_p * max(1, len(bodies)))(*[odelib.raw_pointer(b) for b in bodies])
        r.bodies = ctypes.cast(r.keepalive, ctypes.POINTER(ctypes.c_void_p))
        (p, q) = base.body_offset
        r.T[:] = tuple(p) + tuple(q)
        return r

    def model_actuators_changed(self, actuators):
        self._macts = tuple(actuators)
        self._macts_array = (ctypes.POINTER(MrModelActuator) * max(1, len(self._macts)))(
            *[ctypes.pointer(a.record) for a in self._macts])
        self._stretch.macts, self._stretch.nmacts = ctypes.addressof(self._macts_array), len(self._macts)

    def apply_model_actuators(self, actuators):
        if self._macts:
            self.nat.mr_apply_model_actuators(self._macts_array, len(self._macts))

    def track_turns(self, joints):
        if self._nturns:
            self.nat.mr_track_turns(self._turn_array, self._nturns)

    @staticmethod
    def actuator_gains(r):
        return act.PidGains(r.p, r.i, r.d, r.i_max, r.i_min, bool(r.antiwindup))

    @staticmethod
    def set_actuator_gains(r, g):
        r.p, r.i, r.d, r.i_max, r.i_min = g.p, g.i, g.d, g.i_max, g.i_min
        r.antiwindup = 1 if g.antiwindup else 0

    @staticmethod
    def reset_actuator_pid(r):
        r.p_error_last = r.p_error = r.i_error = r.d_error = r.cmd = 0.0
        r.p_term = r.i_term = r.d_term = 0.0

    @staticmethod
    def actuator_pid_state(r):
        return (r.p_error_last, r.p_error, r.i_error, r.d_error, r.cmd)

    @staticmethod
    def actuator_terms(r):
        return (r.p_error, r.d_error, r.p_term, r.i_term, r.d_term)

    @staticmethod
    def set_actuator_coeffs(r, coeffs):
        r.ncoef = len(coeffs)
        for k, c in enumerate(coeffs):
            r.coef[k] = c

    @staticmethod
    def set_actuator_queue(r, pieces):
        n = len(pieces)
        if n:
            coefs = ctypes.c_double * act.MAX_COEFFS
            made = (MrPiece * n)(*[MrPiece(kind, len(coef), has_off, coefs(*coef), *times)
                                   for kind, coef, has_off, *times in pieces])
            ctypes.memmove(r.queue, made, ctypes.sizeof(made))
        r.nqueue = n
        r.qnext = 0

    def actuator_tracking_error(self, r, joint, t):
        out = self._error_out
        self.nat.mr_actuator_tracking_error(ctypes.byref(r), t, out)
        return out[0], out[1]

    def set_actuator_bodies(self, r, bodies):
        arr = (ctypes.c_void_p * max(1, len(bodies)))(*[odelib.raw_pointer(b) for b in bodies])
        self._body_lists[ctypes.addressof(r)] = arr        # kept alive while the record points at it
        r.bodies = ctypes.addressof(arr)
        r.nbodies = len(bodies)

    def register_geom(self, info):
        e = info.entry
        if e.uid is None:
            e.uid = self._next_uid
            self._next_uid += 1
            free = [i for i, m in enumerate(self._model_slots) if m is None]
            if free:
                e.cindex = free[0]
                self._model_slots[free[0]] = e
            else:
                e.cindex = len(self._model_slots)
                self._model_slots.append(e)
        self.update_geom(info)

    def _surface_idx(self, s):
        key = s.key()
        idx = self._surface_index.get(key)
        if idx is None:
            idx = len(self._surface_index)
            self._surface_index[key] = idx
            self.nat.mr_set_surface(self.ctx, idx, *key)
        return idx

    def update_geom(self, info):
        e = info.entry
        self.nat.mr_set_geom(self.ctx, geom_ptr(info.geom), e.cindex, e.uid, info.group,
                             1 if info.self_collide else 0, self._surface_idx(info.surface))

    def forget_model(self, entry):
        if entry.cindex is not None and entry.cindex < len(self._model_slots) and \
                self._model_slots[entry.cindex] is entry:
            self._model_slots[entry.cindex] = None

    def remove_geom(self, geom):
        """True when the geom is gone entirely (a native mesh); else it still has to leave its space."""
        if isinstance(geom, NativeMesh):
            geom.destroy()
            return True
        if self.ctx is not None:
            self.nat.mr_remove_geom(self.ctx, geom._id())
        return False

    def close(self):
        if self.ctx is not None:
            self.nat.mr_ctx_free(self.ctx)
            self.ctx = None

    # ---- contact watches (noted in mr_near) ---------------------------------------------------
    def new_watch(self, infos):
        w = self.nat.mr_watch_new(self.ctx)
        for i in infos:
            self.nat.mr_watch_add_geom(self.ctx, w, geom_ptr(i.geom))
        return w

    def drain_watch(self, handle):
        if self.ctx is None:
            return []
        room = 16
        while True:
            buf = (ctypes.c_void_p * (2 * room))()
            steps = (ctypes.c_int * room)()
            n = self.nat.mr_watch_drain(self.ctx, handle, buf, steps, room)
            if n <= room:
                break
            room = n
        if n == 0:
            return []
        by_ptr = {geom_ptr(g): info for g, info in self.p.geom_info.items()}
        out = []
        for k in range(n):
            mine, other = by_ptr.get(buf[2 * k]), by_ptr.get(buf[2 * k + 1])
            if mine is not None and other is not None:
                out.append((mine, other, steps[k]))
        return out

    def close_watch(self, handle):
        if self.ctx is not None:
            self.nat.mr_watch_free(self.ctx, handle)

    def rebuild(self, models):
        world = self.p
        nat, ctx = self.nat, self.ctx
        self._effort_joints = ()             # their ODE joints may be gone
        nat.mr_clear_adjacency(ctx)
        for m in models:
            e = world.entries[m]
            for a, b in e.adjacent:
                nat.mr_add_adjacent(ctx, e.uid or 0, a, b)
        nat.mr_set_model_count(ctx, len(self._model_slots))
        # the turn counts of the joints that count turns live here, in C memory, from now on
        unwrap = world.unwrap
        turns = {}
        for j in unwrap:
            rec = self._turns.get(j)
            if rec is None:
                rec = MrTurn()
                rec.joint = odelib.raw_pointer(j.ode_joint)
                j.bind_turn_record(rec)
            turns[j] = rec
        self._turns = turns
        self._nturns = len(unwrap)
        self._turn_array = (ctypes.POINTER(MrTurn) * max(1, len(unwrap)))(
            *[ctypes.pointer(turns[j]) for j in unwrap])
        for a in self._acts:
            self._bind_turn(a.record, a.joint)
            if a.master is not None:
                self.set_actuator_master(a.record, a.master)
        self._arrange_mimics_and_soft(world.mimics, world.soft)
        owners = [(m, g) for m in world.dynamic_models for g in m.dynamic_groups]
        self._body_owner = owners
        self._body_array = (ctypes.c_void_p * max(1, len(owners)))(
            *[odelib.raw_pointer(g.body) for _, g in owners])
        # the guard's snapshots of the C loop, for these bodies and turn records (the World takes
        # what it needs of the last one before a rebuild: World._adopt_native_snapshot)
        self._snap = (ctypes.c_double * (SNAP_BODY * max(1, len(owners))))()
        self._snap_turns = (ctypes.c_double * (2 * max(1, len(unwrap))))()
        self._snap_index = {id(g.body): k for k, (_, g) in enumerate(owners)}
        self._snap_turn_index = {id(j): k for k, j in enumerate(unwrap)}
        b = self._stretch
        b.snap, b.snap_turns = ctypes.addressof(self._snap), ctypes.addressof(self._snap_turns)
        b.snap_iter = -1
        damped = world.damped
        n = len(damped)
        self._damp_arrays = (n, (ctypes.c_void_p * max(1, n))(*[odelib.raw_pointer(j.ode_joint)
                                                                for j, _ in damped]),
                             (ctypes.c_int * max(1, n))(*[0 if j.is_angular else 1 for j, _ in damped]),
                             (ctypes.c_double * max(1, n))(*[c for _, c in damped]))
        dj, dk, dc = self._damp_arrays[1:]
        b.ndamp = n
        b.damp_joints, b.damp_kinds, b.damp_coef = (ctypes.addressof(dj), ctypes.addressof(dk),
                                                    ctypes.addressof(dc))
        b.turns, b.nturns = ctypes.addressof(self._turn_array), self._nturns
        b.bodies, b.nbodies = ctypes.addressof(self._body_array), len(self._body_owner)
        self.settings_changed()     # the time step

    def settings_changed(self):
        world = self.p
        b = self._stretch
        params = world.params
        b.guard_max_contacts = int(params["guard_max_contacts"])
        b.snapshot_interval = int(params["snapshot_interval"])
        b.max_contacts = int(world.max_contacts)
        b.vmax2, b.wmax2 = world.vmax2, world.wmax2
        b.dt = world.dt
        b.gx, b.gy, b.gz = world.gravity
        b.layer = world.layer
        b.world_step = 1 if world.world_step else 0

    def _arrange_mimics_and_soft(self, mimics, soft):
        """The mimic and soft-limit joints for mr_run_steps (after every rebuild)."""
        ok = all(m.ode_joint is not None and (j.is_angular or j.type == "prismatic")
                 and (m.is_angular or m.type == "prismatic") for j, m in mimics)
        self.stretch_ok = ok and all(j.is_angular for j in soft)
        self._mimics = (_Mimic * max(1, len(mimics)))()
        self._softs = (_Soft * max(1, len(soft)))()
        if not self.stretch_ok:
            return

        def turn(j):
            rec = self._turns.get(j)
            return ctypes.pointer(rec) if rec is not None else ctypes.POINTER(MrTurn)()
        for k, (j, m) in enumerate(mimics):
            e = self._mimics[k]
            e.joint, e.master = odelib.raw_pointer(j.ode_joint), odelib.raw_pointer(m.ode_joint)
            e.slider, e.master_slider = (0 if j.is_angular else 1), (0 if m.is_angular else 1)
            e.turn, e.master_turn = turn(j), turn(m)
            e.mult, e.offset = j.mimic[1], j.mimic[2]
            e.has_lower, e.has_upper = int(j.lower is not None), int(j.upper is not None)
            e.lower = j.lower if j.lower is not None else 0.0
            e.upper = j.upper if j.upper is not None else 0.0
            e.child_inertia = j.child_inertia
        for k, j in enumerate(soft):
            e = self._softs[k]
            e.joint, e.turn = odelib.raw_pointer(j.ode_joint), turn(j)
            e.lower, e.upper = j.lower, j.upper
        b = self._stretch
        b.mimics, b.nmimic = self._mimics, len(mimics)
        b.softs, b.nsoft = self._softs, len(soft)

    # ---- native stretches (mr_run_steps) ------------------------------------------------------
    def wake(self):
        """Any thread: the stretch in progress ends after its current step."""
        self._wake.value = 1

    def clear_wake(self):
        """The loop thread, before it asks the due times: a wake from then on ends the next stretch
        (cleared later, a wake between the due times and the stretch would be lost)."""
        self._wake.value = 0

    def set_observer(self, fn, user):
        """``fn(user, t)`` (C function addresses, or None) after every step of a stretch."""
        self._stretch.observer, self._stretch.observer_user = fn, user

    def run(self, n, t, iterations, before_due, after_due, efforts):
        """Up to ``n`` steps in C from time ``t`` (iteration count ``iterations``): none that
        starts at t' >= ``before_due`` (a before-hook is due, or the World's own Python), a step
        ending at t' with t' + 1e-12 >= ``after_due`` ends the stretch (``after``); so do a step the
        guard must look at, the end of a segment actuator's piece and a wake-up. The first step
        applies ``efforts`` ((joints, values): Joint.take_effort's). Returns a Stretch, or None when
        no step was made (the next one is the World's in Python)."""
        b = self._stretch
        joints, values = efforts
        if joints:
            self._hand_efforts(b, joints, values)
        else:
            b.nefforts = 0
        b.time, b.iterations = t, iterations
        b.before_due, b.after_due = before_due, after_due
        k = self._run(self.ctx, self._stretch_ref, int(n))
        if k <= 0:
            return None
        self.ncontacts = b.ncontacts
        self._first_bad.value = b.first_bad
        out = Stretch()
        out.steps, out.time, out.iterations = k, b.time, b.iterations
        out.after, out.guard, out.ncontacts = bool(b.after), bool(b.guard), b.ncontacts
        return out

    def _hand_efforts(self, b, joints, values):
        """The efforts into the stretch (the joints' ODE joints and kinds kept while the same joints
        come again, as a controller's every step brings them)."""
        if joints != self._effort_joints:
            n = len(joints)
            arrays = ((ctypes.c_void_p * n)(*[odelib.raw_pointer(j.ode_joint) for j in joints]),
                      (ctypes.c_int * n)(*[0 if j.is_angular else 1 for j in joints]),
                      (ctypes.c_double * n)())
            self._effort_joints, self._effort_arrays = list(joints), arrays
            b.effort_joints, b.effort_kinds, b.effort_values = [ctypes.addressof(a) for a in arrays]
        self._effort_arrays[2][:] = values
        b.nefforts = len(joints)

    def make_mesh_geom(self, mesh, dynamic, what):
        verts, tris = mesh
        return NativeMesh(self.nat, self.ctx, verts, tris, dynamic), IDENTITY_POSE

    def apply_damping(self):
        n, jp, kinds, coef = self._damp_arrays
        if n:
            self.nat.mr_apply_damping(jp, kinds, coef, n)

    def step(self, dt):
        # one crossing into C per step: collide, quickStep (or dWorldStep), the guard's scan
        world = self.p
        g = world.gravity
        self.ncontacts = self.nat.mr_step_checked(
            self.ctx, dt, g[0], g[1], g[2], world.layer, world.max_contacts, world.world_step,
            self._body_array, len(self._body_owner), world.vmax2, world.wmax2, self._first_bad_ref)
        return self.ncontacts

    @property
    def snapshot_iteration(self):
        return self._stretch.snap_iter

    def drop_snapshot(self):
        self._stretch.snap_iter = -1

    def forget_anchors(self):
        """The contacts' anchors go (the bodies were put elsewhere)."""
        if self.ctx is not None:
            self.nat.mr_anchors_forget(self.ctx)

    def snapshot_readers(self):
        snap, turns = self._snap, self._snap_turns
        index, turn_index = self._snap_index, self._snap_turn_index

        def body(b):
            o = SNAP_BODY * index[id(b)]
            return (tuple(snap[o:o + 3]), tuple(snap[o + 3:o + 7]), tuple(snap[o + 7:o + 10]),
                    tuple(snap[o + 10:o + 13]))

        def joint(j):
            k = turn_index.get(id(j))
            return None if k is None else (int(turns[2 * k + 1]), turns[2 * k])
        return body, joint

    def find_blowups(self):
        """The guard's scan after a step: the velocity scan already ran in C within step()."""
        world = self.p
        nat = self.nat
        owners = self._body_owner
        nb = len(owners)
        vmax2, wmax2 = world.vmax2, world.wmax2
        flagged = []
        i = self._first_bad.value
        if i >= nb:
            i = -1
        while i >= 0:
            m, g = owners[i]
            flagged.append((m, g, velocity_reason(g.body, vmax2, wmax2)))
            k = i + 1
            while k < nb and owners[k][0] is m:
                k += 1
            i = nat.mr_check_bodies(self._body_array, k, nb, vmax2, wmax2) if k < nb else -1
        cmax = world.params["guard_max_contacts"]
        if self.ncontacts > cmax:
            for m in world.dynamic_models:
                n = nat.mr_model_contacts(self.ctx, world.entries[m].cindex)
                if n > cmax and all(f[0] is not m for f in flagged):
                    flagged.append(contact_explosion(m, n, cmax))
        return flagged

    def contacts(self):
        out = []
        n = self.ncontacts
        if n <= 0:
            return out
        m = self._contact_vals
        gs = (ctypes.c_void_p * (2 * n))()
        vals = (ctypes.c_double * (m * n))()
        n = self.nat.mr_contact_log(self.ctx, gs, vals, n)
        by_ptr = {geom_ptr(g): info for g, info in self.p.geom_info.items()}
        for k in range(n):
            i1, i2 = by_ptr.get(gs[2 * k]), by_ptr.get(gs[2 * k + 1])
            if i1 is None or i2 is None:
                continue  # removed since
            v = vals[m * k:m * k + m]
            out.append((i1, i2, tuple(v[0:3]), tuple(v[3:6]), v[6],
                        (tuple(v[7:10]), tuple(v[10:13]), tuple(v[13:16]), tuple(v[16:19]))))
        return out

    def overlaps(self, model):
        """The C collider knows every geom type (also triangle meshes): AABB-overlapping pairs."""
        world = self.p
        found = {}
        others = [(g, i) for g, i in world.geom_info.items() if i.model is not model]
        boxes = {}
        for g, _ in others + [(g, None) for g in model.geoms]:
            if not isinstance(g, ode.GeomPlane):
                boxes[g] = g.getAABB()
        for geom in model.geoms:
            mine = world.geom_info[geom]
            for other, info in others:
                if mine.body is None and info.body is None:
                    continue
                a, b = boxes.get(geom), boxes.get(other)
                if a is not None and b is not None and (a[1] < b[0] or b[1] < a[0] or a[3] < b[2]
                                                        or b[3] < a[2] or a[5] < b[4] or b[5] < a[4]):
                    continue
                d = self.nat.mr_max_depth(geom_ptr(geom), geom_ptr(other))
                key = (model.name, mine.link.name, info.model.name, info.link.name)
                if d > found.get(key, 0.0):
                    found[key] = d
        return found


class NativeMesh(object):
    """A triangle-mesh geom made by the C loop (no PyODE object exists for it); implements the
    few geom methods the builder and the World use."""

    def __init__(self, nat, ctx, verts, tris, dynamic):
        import array
        va = array.array("d", [c for v in verts for c in v])
        ta = array.array("i", [i for t in tris for i in t])
        self._nat = nat
        self._ctx = ctx
        self.ptr = self._nat.mr_mesh_create(self._ctx, va.buffer_info()[0], len(verts),
                                            ta.buffer_info()[0], len(tris), 1 if dynamic else 0)
        self._pos = (0.0, 0.0, 0.0)
        self._quat = (1.0, 0.0, 0.0, 0.0)
        self._body = None

    def setBody(self, body):
        self._body = body  # keeps the PyODE body alive as long as the geom
        self._nat.mr_geom_set_body(self.ptr, odelib.raw_pointer(body) if body is not None else None)

    def setOffsetPosition(self, p):
        self._pos = tuple(p)
        self._nat.mr_geom_set_offset(self.ptr, *(self._pos + self._quat))

    def setOffsetQuaternion(self, q):
        self._quat = tuple(q)
        self._nat.mr_geom_set_offset(self.ptr, *(self._pos + self._quat))

    def setPosition(self, p):
        self._pos = tuple(p)
        self._nat.mr_geom_set_pose(self.ptr, *(self._pos + self._quat))

    def setQuaternion(self, q):
        self._quat = tuple(q)
        self._nat.mr_geom_set_pose(self.ptr, *(self._pos + self._quat))

    def setCategoryBits(self, bits):
        self._cat = bits
        self._nat.mr_geom_set_bits(self.ptr, bits, getattr(self, "_col", bits))

    def setCollideBits(self, bits):
        self._col = bits
        self._nat.mr_geom_set_bits(self.ptr, getattr(self, "_cat", bits), bits)

    def enable(self):
        self._nat.mr_geom_enable(self.ptr, 1)

    def disable(self):
        self._nat.mr_geom_enable(self.ptr, 0)

    def isEnabled(self):
        return bool(self._nat.mr_geom_is_enabled(self.ptr))

    def getAABB(self):
        out = (ctypes.c_double * 6)()
        self._nat.mr_geom_aabb(self.ptr, out)
        return tuple(out)

    def destroy(self):
        if self.ptr:
            self._nat.mr_mesh_destroy(self._ctx, self.ptr)
            self.ptr = None
            self._body = None
