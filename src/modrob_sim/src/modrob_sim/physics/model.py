"""Model, Link and Joint: the objects the contract exposes. They wrap the ODE bodies, geoms and
joints that :mod:`builder` creates; the World steps them.

Frames: every ODE body sits at the centre of mass of its *group* (a link plus every link welded
to it by fixed joints), oriented like the group's root link. Each Link keeps ``_T`` = pose of the
link frame in its body frame, so link poses go both ways without loss (also for links behind
fixed joints, which Gazebo loses).

Each class has two faces: the contract (poses, twists, efforts, wrenches, configuration) and a
*physics-side interface* used by the World and its backends (marked as such below: the ODE
objects, state capture/restore, applying this step's commands). The World calls these and never
touches the objects' private attributes; the builder (:func:`builder.build_model`) is the only
code besides the classes themselves that sets them.
"""
import logging
import math
import weakref

import ode

from ..errors import InputError, SimulationError
from . import odelib
from .limits import JOINT_POSITION_LIMIT, LENGTH_LIMIT
from .transforms import (IDENTITY_POSE, check_pose, check_vec3, cross, pose_inv, pose_mul,
                         quat_from_axis_angle, quat_rotate, from_ode_quat, to_ode_quat,
                         transform_point)

LOG = logging.getLogger("modrob_sim.physics")
TWO_PI = 2.0 * math.pi
#: forces/torques beyond this (N, N m) are clamped before they reach ODE: finite but astronomic
#: values overflow ODE's integrator into NaN, which aborts the process.
FORCE_CAP = 1e9


#: teleport twists beyond this are refused (m/s, rad/s): nothing physical moves that fast, and
#: astronomic values drive ODE's quaternion update to overflow
TWIST_CAP = 1e6
MIMIC_COUPLING_FORCE = 1e4     # N or N m: the largest force a mimic coupling (a linkage) carries
MIMIC_GAIN = 0.5               # share of a mimic joint's position error corrected per step


def _capped(v):
    """Scale a force/torque vector down to FORCE_CAP magnitude."""
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if n > FORCE_CAP:
        k = FORCE_CAP / n
        return (v[0] * k, v[1] * k, v[2] * k)
    return v


def check_twist(lin, ang, what):
    """InputError naming ``what`` when a component of the twist is beyond TWIST_CAP."""
    for v, unit in ((lin, "m/s"), (ang, "rad/s")):
        if max(abs(x) for x in v) > TWIST_CAP:
            raise InputError("%s: %r %s is beyond %g: refused" % (what, v, unit, TWIST_CAP))


def _body_pose(body):
    q = body.getQuaternion()
    return (body.getPosition(), (q[1], q[2], q[3], q[0]))


def _set_body_pose(body, pose):
    body.setPosition(pose[0])
    body.setQuaternion(to_ode_quat(pose[1]))


class Group(object):
    """Links welded together by fixed joints: one ODE body (or none when static)."""
    __slots__ = ("index", "body", "links", "root", "model", "mass", "gravity_mode", "anti_gravity",
                 "static_pose", "_inertia")

    def __init__(self, index, model, root):
        self.index = index
        self.model = model
        self.root = root
        self.links = []
        self.body = None
        self.mass = 0.0
        self.gravity_mode = True
        self.anti_gravity = ()  # ((mass, local com), ...) for links with gravity off in a mixed body
        self.static_pose = None
        self._inertia = None


class Link(object):
    """One URDF/SDF link. ``pose`` is the world pose of the LINK frame (not the inertial frame)."""

    def __init__(self, model, desc):
        self.name = desc.name
        self.model = model
        self.mass = desc.mass
        self.inertia = desc.inertia
        self.inertial_origin = desc.inertial_origin
        self.collisions = desc.collisions  # addition: GeometryDesc list (link frame)
        self.visuals = desc.visuals        # addition: GeometryDesc list (link frame)
        self.sensors = desc.sensors        # addition: <sensor> Elements
        self.extra = getattr(desc, "extra", {})  # addition: accepted <gazebo> tags (laserRetro ...)
        self.material = desc.material
        self.self_collide = desc.self_collide
        self._gravity = desc.gravity
        self._group = None
        self._body = None
        self._T = IDENTITY_POSE      # link frame in body frame (dynamic) ...
        self._static_pose = None     # ... or world pose (static)
        self._geoms = []             # (geom, pose of geom in link frame)
        self._wrenches = []          # [force, torque, local point, remaining or None]
        self.parent_joint = None     # addition: Joint or None

    def __repr__(self):
        return "<Link %s::%s>" % (self.model.name, self.name)

    # ---- state -------------------------------------------------------------------------------
    @property
    def is_static(self):
        return self._body is None

    def _gone(self):
        return SimulationError("link '%s': model '%s' is no longer in the world"
                               % (self.name, self.model.name))

    @property
    def pose(self):
        b = self._body
        if b is None:
            if self._static_pose is None:
                raise self._gone()
            return self._static_pose
        return pose_mul(_body_pose(b), self._T)

    @property
    def twist(self):
        b = self._body
        if b is None:
            if self._static_pose is None:
                raise self._gone()
            return ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        q = b.getQuaternion()
        r = quat_rotate((q[1], q[2], q[3], q[0]), self._T[0])
        v = b.getLinearVel()
        w = b.getAngularVel()
        c = cross(w, r)
        return ((v[0] + c[0], v[1] + c[1], v[2] + c[2]), tuple(w))

    def set_pose(self, pose):
        """Teleport this link's body (the links welded to it move along). Joints to other links
        then pull them together again, as in Gazebo; use Model.set_pose to move a whole model."""
        pose = check_pose(pose, "link '%s' set_pose" % self.name)
        if self._body is None:
            self.model._move_static(pose_mul(pose, pose_inv(self._static_pose)))
            return
        _set_body_pose(self._body, pose_mul(pose, pose_inv(self._T)))
        self._body.enable()
        self.model._after_teleport()

    def set_twist(self, twist):
        lin = check_vec3(twist[0], "link '%s' twist linear" % self.name)
        ang = check_vec3(twist[1], "link '%s' twist angular" % self.name)
        check_twist(lin, ang, "link '%s' set_twist" % self.name)
        b = self._body
        if b is None:
            return
        q = b.getQuaternion()
        r = quat_rotate((q[1], q[2], q[3], q[0]), self._T[0])
        c = cross(ang, r)
        b.setLinearVel((lin[0] - c[0], lin[1] - c[1], lin[2] - c[2]))
        b.setAngularVel(ang)
        b.enable()

    @property
    def gravity_enabled(self):
        return self._gravity

    @gravity_enabled.setter
    def gravity_enabled(self, on):
        self._gravity = bool(on)
        if self._group is not None:
            self.model._world.group_gravity_changed(self._group)

    # ---- physics-side interface (World and backends) -------------------------------------------
    @property
    def body(self):
        """The ODE body this link is part of (None when static or removed)."""
        return self._body

    @property
    def group(self):
        """The Group (links welded by fixed joints) this link belongs to."""
        return self._group

    @property
    def body_offset(self):
        """Pose of the link frame in its body's frame."""
        return self._T

    @property
    def has_wrenches(self):
        return bool(self._wrenches)

    def apply_wrenches(self, dt):
        """Add this step's wrenches to the body; drop those whose duration ran out. Returns True
        while some remain."""
        b = self._body
        keep = []
        for w in self._wrenches:
            f, tq, p, remaining = w
            if b is not None:
                b.enable()
                q = b.getQuaternion()
                bp = b.getPosition()
                pw = transform_point(((bp[0], bp[1], bp[2]), (q[1], q[2], q[3], q[0])),
                                     transform_point(self._T, p))
                b.addForceAtPos(f, pw)
                b.addTorque(tq)
            if remaining is not None:
                remaining -= dt
                if remaining <= 1e-12:
                    continue
                w[3] = remaining
            keep.append(w)
        self._wrenches = keep
        return bool(keep)

    def release(self):
        """The model left the world: forget the ODE objects."""
        self._geoms = []
        self._body = None
        self._wrenches = []

    @property
    def collision_names(self):
        """(addition) Gazebo's names of the link's collisions, in order: the name given, else
        ``<link>_collision`` for the first and ``<link>_collision_<i>`` for the i-th after it."""
        return [g.name or ("%s_collision" % self.name if i == 0 else "%s_collision_%d" % (self.name, i))
                for i, g in enumerate(self.collisions)]

    # ---- wrenches ----------------------------------------------------------------------------
    @property
    def collides(self):
        """(addition) False while :meth:`set_collides` turned the link's collisions off."""
        return all(g.isEnabled() for g, _ in self._geoms)

    def set_collides(self, on):
        """(addition) Turn every collision of the link on or off (Gazebo's
        ``Link::SetCollideMode("all")`` / ``("none")``): an off geom makes no contacts. The body is
        woken (a resting body that loses its contacts must fall)."""
        for g, _ in self._geoms:
            if on:
                g.enable()
            else:
                g.disable()
        if self._body is not None:
            self._body.enable()

    def add_wrench(self, force, torque, reference_point=(0.0, 0.0, 0.0), duration=None):
        """Force and torque in the WORLD frame; ``reference_point`` in the LINK frame (where the
        force acts, relative to the link origin). Applied every step until ``duration`` simulated
        seconds have passed (None: until clear_wrenches())."""
        what = "link '%s' of model '%s' add_wrench" % (self.name, self.model.name)
        f = _capped(check_vec3(force, what + " force"))
        t = _capped(check_vec3(torque, what + " torque"))
        p = check_vec3(reference_point, what + " reference_point")
        if max(abs(x) for x in p) > LENGTH_LIMIT:
            raise InputError("%s: reference_point %r is beyond %g m from the link origin (limits: "
                             "docs/simulator.md); nothing applied" % (what, p, LENGTH_LIMIT))
        if duration is not None:
            duration = float(duration)
            if not math.isfinite(duration) or duration <= 0:
                raise InputError("%s: duration must be a positive number of seconds or None" % what)
        if self._body is None:
            return
        self._wrenches.append([f, t, p, duration])
        self.model._world.queue_wrench(self)

    def clear_wrenches(self):
        del self._wrenches[:]


class Joint(object):
    """One URDF/SDF joint; positions in rad or m. Continuous joints accumulate (no wrap)."""

    def __init__(self, model, desc):
        self.name = desc.name
        self.type = desc.type
        self.parent = desc.parent
        self.child = desc.child
        self.axis = desc.axis
        self.origin = desc.origin  # addition: joint frame in the parent link frame
        self._child_offset = desc.child_offset
        self.lower = desc.lower
        self.upper = desc.upper
        self.effort_limit = desc.effort_limit
        self.velocity_limit = desc.velocity_limit
        self.damping = desc.damping
        self.friction = desc.friction
        self.mimic = desc.mimic
        self.model = model
        self._effort = 0.0
        self._actuator = None      # the World's actuator of this joint (world.add_actuator), or None
        self._ode = None
        self._angular = desc.type in ("revolute", "continuous")
        self._linear = desc.type == "prismatic"
        self._tr = TurnRecord()    # whole turns counted; the native backend puts its own record here
        self._unwrap = False       # revolute without stops inside (-pi, pi]: track turns
        self._soft_limits = False  # revolute limits beyond +-pi: stops moved each step
        self._cmd = 0.0
        self._raw_cmd = 0.0
        self._has_cmd = False
        self._vel_target = None    # (v, fmax)
        self._child_inertia = 1.0  # about the axis; bounds the explicit damping for stability
        self._fb_armed_at = None   # world iteration at which measure_wrench turned ODE's feedback on

    def __repr__(self):
        return "<Joint %s::%s (%s)>" % (self.model.name, self.name, self.type)

    @property
    def effort(self):
        """The effort applied in the last step (after clamping; an actuator's included)."""
        a = self._actuator
        return a.applied if a is not None else self._effort

    @effort.setter
    def effort(self, f):
        a = self._actuator
        if a is not None:
            a.record.applied = f
        self._effort = f

    @property
    def actuator(self):
        """The World's actuator driving this joint, or None."""
        return self._actuator

    @property
    def _turns(self):
        return self._tr.turns

    @_turns.setter
    def _turns(self, n):
        self._tr.turns = n

    @property
    def _last_raw(self):
        return self._tr.last_raw

    @_last_raw.setter
    def _last_raw(self, raw):
        self._tr.last_raw = raw

    @property
    def position(self):
        j = self._ode
        if j is None:
            return 0.0
        if self._angular:
            return j.getAngle() + TWO_PI * self._tr.turns
        return j.getPosition()

    @property
    def velocity(self):
        j = self._ode
        if j is None:
            return 0.0
        if self._angular:
            return j.getAngleRate()
        return j.getPositionRate()

    def limit_effort(self, f):
        """``f`` clamped to +-effort_limit (when positive) and +-FORCE_CAP: what the joint takes."""
        lim = self.effort_limit
        if lim is not None and lim > 0.0:
            if f > lim:
                return lim
            if f < -lim:
                return -lim
        if f > FORCE_CAP:
            return FORCE_CAP
        if f < -FORCE_CAP:
            return -FORCE_CAP
        return f

    def _bounded_position(self, q):
        """A position to teleport to: refused beyond JOINT_POSITION_LIMIT (ValueError), clamped
        into [lower, upper] with a warning (the joint's stops would otherwise fire it back)."""
        if abs(q) > JOINT_POSITION_LIMIT:
            raise InputError("model '%s' joint '%s': position %g is beyond %g (limits: "
                             "docs/simulator.md); nothing changed"
                             % (self.model.name, self.name, q, JOINT_POSITION_LIMIT))
        lo, hi = self.lower, self.upper
        if lo is not None and hi is not None and not lo <= q <= hi:
            c = min(max(q, lo), hi)
            LOG.warning("model '%s' joint '%s': position %g is outside its limits [%g, %g]: set to %g",
                        self.model.name, self.name, q, lo, hi, c)
            return c
        return q

    def _check_effort(self, f):
        try:
            f = float(f)
        except (TypeError, ValueError):
            raise InputError("joint '%s' of model '%s': effort %r is not a number"
                             % (self.name, self.model.name, f))
        if not math.isfinite(f):
            raise InputError("joint '%s' of model '%s': effort %r is not finite; nothing applied"
                             % (self.name, self.model.name, f))
        if self._ode is None:
            raise InputError("joint '%s' of model '%s' is %s: it takes no effort"
                             % (self.name, self.model.name, self.type))
        return f

    def _queue(self):
        if not self._has_cmd:
            self._has_cmd = True
            self.model._world.queue_effort(self)

    def set_effort(self, f):
        """Effort (N m or N) for the NEXT step only; clamped to +-effort_limit. Several calls in one
        step: the last one wins (use add_effort to accumulate)."""
        if f.__class__ is float and -FORCE_CAP <= f <= FORCE_CAP and self._ode is not None:
            # a controller's every call: the checks below, inline (their calls were a third of a
            # PD loop's Python per step)
            lim = self.effort_limit
            self._raw_cmd = f
            if lim is not None and lim > 0.0:
                f = lim if f > lim else (-lim if f < -lim else f)
            self._cmd = f
        else:
            f = self._check_effort(f)
            self._raw_cmd = f
            self._cmd = self.limit_effort(f)
        if not self._has_cmd:
            self._has_cmd = True
            self.model._world.queue_effort(self)

    def add_effort(self, f):
        """Addition to the contract: like Gazebo's Joint::SetForce, efforts given in one step add
        up (the sum is clamped to +-effort_limit) and last for that step only."""
        f = self._check_effort(f)
        self._raw_cmd = (self._raw_cmd if self._has_cmd else 0.0) + f
        self._cmd = self.limit_effort(self._raw_cmd)
        self._queue()

    def set_position(self, q):
        """Kinematic: teleports the child subtree; the joint ends with zero velocity."""
        self.model.set_configuration([self.name], [q])

    def set_velocity_target(self, v, max_force):
        """ODE joint motor (ros_control's velocity interface): drive towards velocity ``v`` with at
        most ``max_force``; ``max_force`` 0 disables it (the <dynamics friction> motor returns).
        ``v`` is clamped to +-velocity_limit when that is positive."""
        what = "joint '%s' of model '%s' set_velocity_target" % (self.name, self.model.name)
        try:
            v, fm = float(v), float(max_force)
        except (TypeError, ValueError):
            raise InputError("%s: velocity and max_force must be numbers" % what)
        if not (math.isfinite(v) and math.isfinite(fm)):
            raise InputError("%s: non-finite velocity %r or max_force %r; nothing applied"
                             % (what, v, max_force))
        if fm < 0:
            raise InputError("%s: max_force must not be negative" % what)
        if self._ode is None:
            raise InputError("%s: a %s joint has no motor" % (what, self.type))
        vl = self.velocity_limit
        if vl is not None and vl > 0:
            v = max(-vl, min(vl, v))
        fm = min(fm, FORCE_CAP)
        self._vel_target = (v, fm) if fm > 0 else None
        self._apply_motor()

    # ---- the wrench the joint transmits (addition) -----------------------------------------------
    @property
    def child_offset(self):
        """The child link frame in the joint frame (identity for URDF; SDF's joint <pose>)."""
        return self._child_offset

    @property
    def can_measure_wrench(self):
        """False for a joint welded into one body (fixed joints: no ODE joint carries anything)."""
        return self._ode is not None

    def measure_wrench(self):
        """From the next step on, ODE reports what this joint's constraints do (its joint
        feedback, kept for the model's life). Returns False when the joint has no ODE joint."""
        if self._ode is None:
            return False
        if self._fb_armed_at is None:
            self._ode.setFeedback(True)
            self._fb_armed_at = self.model._world.iterations   # ODE writes it from the next step
        return True

    def transmitted_wrench(self):
        """``(force, torque)`` the joint exerted on its CHILD in the last step, world frame, torque
        about the joint origin: ODE's constraint rows (stops, motors, mimic coupling, friction) plus
        the effort applied to the joint (``effort``). Explicit damping is not included. None until
        :meth:`measure_wrench` was called and a step was made since."""
        o = self._ode
        if o is None or self._fb_armed_at is None or self._fb_armed_at == self.model._world.iterations:
            return None
        fb = o.getFeedback()
        f, t = list(fb[0]), list(fb[1])
        e = self.effort
        if e:
            ax = o.getAxis()
            acc = t if self._angular else f
            for k in range(3):
                acc[k] += e * ax[k]
        body = self._ode.getBody(0)
        cg = body.getPosition()
        child = self.model.links[self.child]
        origin = pose_mul(child.pose, pose_inv(self._child_offset))[0]   # the joint frame's
        arm = (cg[0] - origin[0], cg[1] - origin[1], cg[2] - origin[2])
        m = cross(arm, f)
        return tuple(f), (t[0] + m[0], t[1] + m[1], t[2] + m[2])

    # ---- physics-side interface (World and backends) -------------------------------------------
    @property
    def ode_joint(self):
        """The ODE joint (None for fixed joints and removed models)."""
        return self._ode

    @property
    def is_angular(self):
        return self._angular

    @property
    def child_inertia(self):
        """Inertia (kg m^2) or mass (kg) of the child body about/along the axis."""
        return self._child_inertia

    @property
    def tracks_turns(self):
        """True for an angular joint whose position counts whole turns (no stops inside +-pi)."""
        return self._unwrap

    @property
    def turn_state(self):
        """(whole turns counted, last raw ODE angle) of a turn-tracking joint."""
        return self._turns, self._last_raw

    @property
    def turn_record(self):
        """The record that holds the turn count (``turns``, ``last_raw``)."""
        return self._tr

    def bind_turn_record(self, record):
        """Keep the turn count in ``record`` from now on (the native backend's C memory, which its
        steps update); the count so far is copied into it."""
        record.turns, record.last_raw = self._tr.turns, self._tr.last_raw
        self._tr = record

    def bind_actuator(self, actuator):
        """The World's actuator of this joint (None: none)."""
        self._actuator = actuator

    def take_command(self):
        """The raw sum of the efforts given for this step (None when none) and forget them: the
        World hands them to the joint's actuator, which adds them before the joint's clamp."""
        if not self._has_cmd:
            return None
        raw = self._raw_cmd
        self._cmd = 0.0
        self._has_cmd = False
        return raw

    def add_raw_effort(self, f):
        """Apply ``f`` (already clamped) to the ODE joint for this step (the actuators)."""
        if self._angular:
            self._ode.addTorque(f)
        else:
            self._ode.addForce(f)

    def drive_motor(self, v, max_force):
        """The ODE joint motor towards velocity ``v`` with at most ``max_force`` this step (MOTOR
        actuators and OUT_VELOCITY outputs)."""
        self._ode.setParam(odelib.PARAM_VEL, v)
        self._ode.setParam(odelib.PARAM_FMAX, max_force)

    def release_motor(self):
        """An actuator stopped driving the ODE motor: the joint's own motor again (its
        set_velocity_target, else its <dynamics friction>)."""
        self._apply_motor()

    @property
    def has_soft_limits(self):
        """True for revolute limits beyond +-pi (ODE's stops are moved with the turn count)."""
        return self._soft_limits

    def take_effort(self):
        """The effort queued for this step, clamped, handed to the step that applies it (the
        World's, with add_raw_effort, or the native backend's): reported in ``effort`` from now on
        and forgotten."""
        f = self._effort = self._cmd
        self._cmd = 0.0
        self._has_cmd = False
        return f

    def add_damping(self, coefficient):
        """Explicit viscous damping for this step: -coefficient * velocity."""
        o = self._ode
        if self._angular:
            o.addTorque(-coefficient * o.getAngleRate())
        else:
            o.addForce(-coefficient * o.getPositionRate())

    def track_turns(self):
        """After a step: count a whole turn when ODE's raw angle wrapped across +-pi."""
        raw = self._ode.getAngle()
        d = raw - self._last_raw
        if d > math.pi:
            self._turns -= 1
        elif d < -math.pi:
            self._turns += 1
        self._last_raw = raw

    def update_soft_limits(self):
        """Revolute limits beyond +-pi: ODE stops only work on the raw angle in (-pi, pi], so move
        them with the turn count each step."""
        k = TWO_PI * self._turns
        lo, hi = self.lower - k, self.upper - k
        o = self._ode
        o.setParam(odelib.PARAM_LO_STOP, lo if lo > -math.pi else -ode.Infinity)
        o.setParam(odelib.PARAM_HI_STOP, hi if hi < math.pi else ode.Infinity)

    def drive_mimic(self, master, dt):
        """The mimic coupling as a stiff velocity constraint solved inside ODE's LCP (the joint's
        motor row): target velocity = MIMIC_GAIN * (multiplier * q_master + offset - q) / dt, so
        the error halves every step. It stands for a linkage, not a second actuator: its force is
        bounded by MIMIC_COUPLING_FORCE and NOT by the mimic joint's effort limit (bounded by the
        grip force, a mimic finger pressed by its master with that same force gave way). No
        feed-forward of the master's velocity: that velocity is one step old, and through a
        squeezed object the delay closed a loop that made the fingers chatter and lose it."""
        mult, off = self.mimic[1], self.mimic[2]
        q = self.position
        v = MIMIC_GAIN * (master.position * mult + off - q) / dt
        fmax = MIMIC_COUPLING_FORCE
        if (self.lower is not None and q <= self.lower) or (self.upper is not None and q >= self.upper):
            # At a stop ODE applies a powered motor's whole force EXPLICITLY (one LCP row for
            # both): bound it by what reaches the target velocity in this step.
            fmax = min(fmax, self._child_inertia * abs(v - self.velocity) / dt)
        self._ode.setParam(odelib.PARAM_VEL, v)
        self._ode.setParam(odelib.PARAM_FMAX, fmax)

    def set_mimic(self, mimic):
        """(World.set_mimic) the coupling ``(master name, multiplier, offset)`` or None; a joint
        released from it gets its own motor settings back (friction, velocity target)."""
        self.mimic = mimic
        if mimic is None:
            self._apply_motor()

    def release(self):
        """The model left the world: detach and forget the ODE joint."""
        if self._ode is not None:
            self._ode.attach(None, None)
        self._ode = None

    def _apply_motor(self):
        j = self._ode
        if j is None or self.mimic is not None:
            return
        if self._vel_target is not None:
            j.setParam(odelib.PARAM_VEL, self._vel_target[0])
            j.setParam(odelib.PARAM_FMAX, self._vel_target[1])
        else:
            j.setParam(odelib.PARAM_VEL, 0.0)
            j.setParam(odelib.PARAM_FMAX, self.friction)
        b = j.getBody(0)
        if b is not None:
            b.enable()

    def turned_to(self, q):
        """An actuator set the joint kinematically to ``q`` (OUT_POSITION, pure-Python backend):
        the turn count so that position == q."""
        self._resync_turns(q)

    def _resync_turns(self, q):
        """After a teleport: choose the turn count so that position == q."""
        if self._angular and self._ode is not None:
            raw = self._ode.getAngle()
            self._turns = int(round((q - raw) / TWO_PI)) if self._unwrap else 0
            self._last_raw = raw


class Model(object):
    """A spawned model. Built by :func:`builder.build_model`; see the contract for the API."""

    def __init__(self, world, desc, robot_namespace):
        self._world = weakref.proxy(world)  # weak: see World._finalizer
        self.name = desc.name
        self.kind = desc.kind
        self.source_xml = desc.source_xml
        self.robot_namespace = robot_namespace
        self.plugins = []
        self.links = {}
        self.joints = {}
        self.canonical_link = None
        self.spawn_pose = IDENTITY_POSE
        self.is_static = False
        self._groups = []
        self._dyn_groups = []
        self._bodies = []         # ODE bodies, in group order
        self._geoms = []          # every ODE geom (PyODE frees unreferenced geoms)
        self._ode_joints = []     # every ODE joint of the model
        self._joint_order = []    # joints, parents before children
        self._world_pose = IDENTITY_POSE   # the frame of a 'world' root link (spawn pose)
        self._world_attached = False       # a joint to 'world' that is not fixed (anchors in world)
        self._spawn_state = None
        self._snapshot_state = None
        self._slot = 0
        self._root_name = None
        self._adjacent = frozenset()  # (group index, group index) pairs joined by a joint
        self._ncontacts = 0
        self._grippers = []
        self._removed = False

    def __repr__(self):
        return "<Model %s>" % self.name

    # ---- pose and twist ----------------------------------------------------------------------
    @property
    def pose(self):
        return self.canonical_link.pose

    @property
    def twist(self):
        return self.canonical_link.twist

    def set_pose(self, pose):
        pose = check_pose(pose, "model '%s' set_pose" % self.name)
        delta = pose_mul(pose, pose_inv(self.canonical_link.pose))
        if self._world_attached:
            q = {j.name: j.position for j in self._joint_order if j._ode is not None}
            self._world_pose = pose_mul(delta, self._world_pose)
            self._move_static(delta, only_static=True)
            self._place_zero_configuration()
            self._reset_joint_frames()
            self._apply_configuration(q, rigid_velocity=True)
        else:
            self._move_static(delta)
        self._after_teleport()

    def set_twist(self, twist):
        lin = check_vec3(twist[0], "model '%s' twist linear" % self.name)
        ang = check_vec3(twist[1], "model '%s' twist angular" % self.name)
        check_twist(lin, ang, "model '%s' set_twist" % self.name)
        self.apply_twist(lin, ang)

    def apply_twist(self, lin, ang):
        """set_twist past its checks (physics side: the World's model actuators at every step):
        every body moves with the rigid twist of the canonical link's frame."""
        p0 = self.canonical_link.pose[0]
        for b in self._bodies:
            p = b.getPosition()
            c = cross(ang, (p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]))
            b.setLinearVel((lin[0] + c[0], lin[1] + c[1], lin[2] + c[2]))
            b.setAngularVel(ang)
            b.enable()

    def _move_static(self, delta, only_static=False):
        """Apply the rigid transform ``delta`` (world frame) to every static link and, unless
        only_static, to every body (velocities rotated with it)."""
        self._world_pose = pose_mul(delta, self._world_pose) if not only_static else self._world_pose
        for g in self._groups:
            if g.body is None:
                for ln in g.links:
                    ln._static_pose = pose_mul(delta, ln._static_pose)
                    for geom, rel in ln._geoms:
                        self._world.place_static_geom(geom, pose_mul(ln._static_pose, rel))
            elif not only_static:
                b = g.body
                _set_body_pose(b, pose_mul(delta, _body_pose(b)))
                b.setLinearVel(quat_rotate(delta[1], b.getLinearVel()))
                b.setAngularVel(quat_rotate(delta[1], b.getAngularVel()))
                b.enable()

    # ---- configuration -----------------------------------------------------------------------
    def set_configuration(self, names, positions):
        """Teleport joints (works while running): the named joints take the given positions and
        zero velocity; links below them move rigidly with their parents. Mimic joints follow."""
        names = list(names)
        positions = list(positions)
        if len(names) != len(positions):
            raise InputError("model '%s' set_configuration: %d names but %d positions"
                             % (self.name, len(names), len(positions)))
        targets = {}
        for n, q in zip(names, positions):
            j = self.joints.get(n)
            if j is None:
                raise InputError("model '%s' has no joint '%s' (joints: %s)"
                                 % (self.name, n, ", ".join(sorted(self.joints)) or "none"))
            try:
                q = float(q)
            except (TypeError, ValueError):
                raise InputError("model '%s' joint '%s': position %r is not a number"
                                 % (self.name, n, q))
            if not math.isfinite(q):
                raise InputError("model '%s' joint '%s': position %r is not finite" % (self.name, n, q))
            if j.type in ("fixed", "floating", "planar"):
                raise InputError("model '%s' joint '%s' is %s: it has no position to set"
                                 % (self.name, n, j.type))
            targets[n] = j._bounded_position(q)
        if not targets:
            return
        self._apply_configuration(targets, rigid_velocity=False)
        self._after_teleport()

    def _fk(self, targets):
        """World poses of all links with joint positions from ``targets`` (others: current)."""
        poses = {"world": self._world_pose}
        root = self._root_name
        if root != "world":
            poses[root] = self.links[root].pose
        for j in self._joint_order:
            if j.mimic is not None and j.name not in targets and j.mimic[0] in targets:
                q = targets[j.mimic[0]] * j.mimic[1] + j.mimic[2]
                targets[j.name] = q
        for j in self._joint_order:
            parent = poses[j.parent]
            t = j.type
            if t == "fixed":
                rel = j.origin
            elif t in ("revolute", "continuous"):
                q = targets[j.name] if j.name in targets else j.position
                rel = pose_mul(j.origin, ((0.0, 0.0, 0.0), quat_from_axis_angle(j.axis, q)))
            elif t == "prismatic":
                q = targets[j.name] if j.name in targets else j.position
                a = j.axis
                rel = pose_mul(j.origin, ((a[0] * q, a[1] * q, a[2] * q), (0.0, 0.0, 0.0, 1.0)))
            else:  # floating / planar: keep the measured relative pose
                cur_parent = self._world_pose if j.parent == "world" else self.links[j.parent].pose
                rel = pose_mul(pose_inv(cur_parent), self.links[j.child].pose)
            if j._child_offset is not IDENTITY_POSE and t not in ("floating", "planar"):
                rel = pose_mul(rel, j._child_offset)
            poses[j.child] = pose_mul(parent, rel)
        return poses

    def _apply_configuration(self, targets, rigid_velocity):
        targets = dict(targets)
        current = {j.name: j.position for j in self._joint_order if j._angular}
        poses = self._fk(targets)
        # velocities: the moved subtree moves rigidly with the parent of each set joint
        moved = set()
        for j in self._joint_order:
            if j.name in targets or j.parent in moved:
                moved.add(j.child)
        old_vel = {}
        for g in self._dyn_groups:
            old_vel[g.index] = (g.body.getLinearVel(), g.body.getAngularVel(), g.body.getPosition())
        for g in self._dyn_groups:
            _set_body_pose(g.body, pose_mul(poses[g.root.name], pose_inv(g.root._T)))
        for j in self._joint_order:
            if j.child not in moved and not rigid_velocity:
                continue
            child = self.links[j.child]
            if child._group.root is not child or child._body is None:
                continue
            pl = self.links.get(j.parent)
            body = child._body
            if pl is None or pl._body is None:
                body.setLinearVel((0.0, 0.0, 0.0))
                body.setAngularVel((0.0, 0.0, 0.0))
                continue
            pb = pl._body
            w = pb.getAngularVel()
            v = pb.getLinearVel()
            pp, cp = pb.getPosition(), body.getPosition()
            c = cross(w, (cp[0] - pp[0], cp[1] - pp[1], cp[2] - pp[2]))
            if j.type in ("floating", "planar") and j.name not in targets:
                lv, av, _ = old_vel[child._group.index]
                body.setLinearVel(lv)
                body.setAngularVel(av)
            else:
                body.setLinearVel((v[0] + c[0], v[1] + c[1], v[2] + c[2]))
                body.setAngularVel(w)
        for j in self._joint_order:
            if j._angular:
                j._resync_turns(targets.get(j.name, current[j.name]))
        for b in self._bodies:
            b.enable()

    def _place_zero_configuration(self):
        """Put every body where it is in the zero configuration (the frame the ODE joints were
        built in), from the current root placement."""
        zero = {j.name: 0.0 for j in self._joint_order if j._ode is not None}
        poses = self._fk(zero)
        for g in self._dyn_groups:
            _set_body_pose(g.body, pose_mul(poses[g.root.name], pose_inv(g.root._T)))

    def _reset_joint_frames(self):
        """Re-anchor every ODE joint from the current (zero-configuration) body placement."""
        for j in self._joint_order:
            if j._ode is None:
                continue
            parent_pose = self._world_pose if j.parent == "world" else self.links[j.parent].pose
            frame = pose_mul(parent_pose, j.origin)
            axis = quat_rotate(frame[1], j.axis)
            if j._angular:
                j._ode.setAnchor(frame[0])
                j._ode.setAxis(axis)
            else:
                j._ode.setAxis(axis)
            j._turns = 0
            j._last_raw = 0.0

    # ---- physics-side interface (World and backends) -------------------------------------------
    @property
    def bodies(self):
        """The model's ODE bodies, one per dynamic Group, in group order."""
        return tuple(self._bodies)

    @property
    def geoms(self):
        """Every ODE geom of the model."""
        return tuple(self._geoms)

    @property
    def groups(self):
        return tuple(self._groups)

    @property
    def dynamic_groups(self):
        """The Groups that have a body."""
        return tuple(self._dyn_groups)

    def subtree_bodies(self, joint):
        """The ODE bodies of the links below ``joint`` (its child link and every descendant),
        each once, in group order: what turns with the joint when it is set kinematically."""
        below = {joint.child}
        for j in self._joint_order:
            if j.parent in below:
                below.add(j.child)
        return [g.body for g in self._dyn_groups if any(ln.name in below for ln in g.links)]

    @property
    def joints_in_order(self):
        """Every joint, parents before children."""
        return tuple(self._joint_order)

    @property
    def articulated(self):
        """True when the model has ODE joints (not only welded links)."""
        return bool(self._ode_joints)

    @property
    def world_attached(self):
        """True when a non-fixed joint anchors the model to the world."""
        return self._world_attached

    @property
    def removed(self):
        return self._removed

    def add_geom(self, geom):
        self._geoms.append(geom)

    def wake(self):
        for b in self._bodies:
            b.enable()

    def state_finite(self):
        """False when a body's pose has NaN/inf in it."""
        for b in self._bodies:
            for v in b.getPosition() + b.getQuaternion():
                if not math.isfinite(v):
                    return False
        return True

    def apply_configuration(self, targets):
        """Teleport joints to ``targets`` ({name: position}, already checked) without the
        teleport notification: for the World while it builds the model."""
        self._apply_configuration(targets, rigid_velocity=False)

    def close_grippers(self):
        for g in self._grippers:
            g.close()

    def release(self):
        """The model left the world: forget every ODE object (the World removed the geoms)."""
        for ln in self.links.values():
            ln.release()
        for j in self.joints.values():
            j.release()
        self._geoms = []
        self._ode_joints = []
        self._removed = True
        for g in self._groups:
            g.body = None
        self._bodies = []
        self._dyn_groups = []

    def _after_teleport(self):
        self._world.model_teleported(self)

    # ---- state snapshots (spawn state, guard) ------------------------------------------------
    def capture_state(self, body=None, joint=None):
        """An opaque snapshot of every body and joint turn count (restore_state takes it).
        ``body(b)`` / ``joint(j)`` (optional): a body's (position, quaternion, linear and angular
        velocity) and a joint's (turns, last raw angle, or None: its own) as the native loop's guard
        snapshot holds them, instead of their values now."""
        if body is None:
            bodies = [(b.getPosition(), b.getQuaternion(), b.getLinearVel(), b.getAngularVel())
                      for b in self._bodies]
        else:
            bodies = [body(b) for b in self._bodies]
        joints = [(j._turns, j._last_raw) for j in self._joint_order]
        if joint is not None:
            joints = [joint(j) or own for j, own in zip(self._joint_order, joints)]
        statics = [(ln, ln._static_pose) for g in self._groups if g.body is None for ln in g.links]
        return (bodies, joints, statics, self._world_pose)

    def restore_state(self, state, zero_velocity):
        bodies, joints, statics, world_pose = state
        if world_pose != self._world_pose or any(ln._static_pose != p for ln, p in statics):
            # the base was moved since: put it back and re-anchor joints to the world
            self._world_pose = world_pose
            for ln, p in statics:
                ln._static_pose = p
                for geom, rel in ln._geoms:
                    self._world.place_static_geom(geom, pose_mul(p, rel))
            if self._world_attached:
                self._place_zero_configuration()
                self._reset_joint_frames()
        for b, (p, q, v, w) in zip(self._bodies, bodies):
            b.setPosition(p)
            b.setQuaternion(q)
            if zero_velocity:
                b.setLinearVel((0.0, 0.0, 0.0))
                b.setAngularVel((0.0, 0.0, 0.0))
            else:
                b.setLinearVel(v)
                b.setAngularVel(w)
            b.enable()
        for j, (t, r) in zip(self._joint_order, joints):
            j._turns, j._last_raw = t, r
        for ln in self.links.values():
            ln.clear_wrenches()
        for j in self._joint_order:
            j._cmd = 0.0
            j.effort = 0.0


class TurnRecord(object):
    """Whole turns counted by a joint and its last raw ODE angle (the pure-Python path's; the
    native backend binds a C record with the same fields)."""
    __slots__ = ("turns", "last_raw")

    def __init__(self):
        self.turns = 0
        self.last_raw = 0.0


__all__ = ["Model", "Link", "Joint", "Group", "from_ode_quat", "FORCE_CAP"]
