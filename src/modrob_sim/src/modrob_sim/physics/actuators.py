"""Actuators: what drives a joint at every step, owned by the World (docs/design/sim_core_api.md,
"Actuators"), as MuJoCo's actuator layer or ros_control's command handles.

A controller writes a set-point (an effort, a position or velocity target, a trajectory segment,
a wheel's velocity) and reads back what the last step did; the World's backend runs the actuator
at every step, in Python steps and in its native stretches alike: :func:`step_python` on the
pure-Python backend, ``mr_apply_actuators`` of native/modrob_ode_native.c on the native one (one
implementation per backend, the same operations in the same order).

Per step, from the joint's state at the step's start (what a controller's read sees):

==============  ========================================================================
EFFORT          out = command (held until changed)
POSITION_PID    out = PID(error(command, q))          error: PLAIN, CLAMPED or SHORTEST
VELOCITY_PID    out = PID(command - dq)
SEGMENT_PID     desired (p, v) from the segment; out = PID(e, e_dot) + ff * v with the
                tracking error (e, e_dot) = :func:`tracking_error`: (p - q or, SHORTEST, the
                shortest angle from q to p; v - dq)
MOTOR           ODE joint motor: velocity ramped towards command by at most accel * dt,
                force at most max_force (a wheel's motor); out = 0
FOLLOW_PID      set-point multiplier * q_master + offset (``follow``: a joint of the model,
                its position as Joint.position gives it; the joint itself: a set-point
                relative to where it is); out = PID(set-point - q) + bias when
                |set-point - q| >= deadband, else bias and the PID not advanced. The PID's
                derivative: the error's change (a mimic joint held by a PID: roboticsgroup's
                mimic joint plugin with <hasPID>), or, with a target ``velocity``, velocity
                - dq (franka_gazebo's gripper fingers, each following the other); no
                master: out = 0
==============  ========================================================================

Every actuator of a step reads its joint's state (and a FOLLOW_PID its master's position) before
any of them acts, so that the order in which they are applied changes nothing (an OUT_POSITION
actuator moves links within the step; two FOLLOW_PID actuators may follow each other).

then what the joint gets depends on the actuator's OUTPUT:

==============  ========================================================================
OUT_EFFORT      the effort joint_limit(hardware_clamp(out, finite) + efforts given with
                set_effort/add_effort in that step), capped at FORCE_CAP (the default)
OUT_VELOCITY    out (finite) is a velocity: the joint's ODE motor drives towards
                clamp(out, +-velocity_limit) with at most max_force, as gazebo_ros_control's
                velocity joint without pid_gains; efforts given with set_effort are applied
                as efforts beside it (joint_limit, FORCE_CAP)
OUT_POSITION    no PID: the kind's SET-POINT (EFFORT, POSITION_PID: the command; SEGMENT_PID:
                the segment's desired position) is the joint's position, set kinematically
                as gazebo_ros_control's position joint without pid_gains sets it: first
                saturated as joint_limits_interface's PositionJointSaturationHandle does
                (:func:`saturate_position`: the short way on a continuous joint, at most
                velocity_limit * dt from the last set-point, into [lower, upper]), then the
                links below the joint turned (slid) rigidly about its axis by the difference,
                moving with the joint's parent link (the joint's velocity 0); efforts given
                with set_effort are applied as efforts (joint_limit, FORCE_CAP)
==============  ========================================================================

A SEGMENT_PID actuator's piece (a segment valid for steps starting before its end, or a hold) may
have up to MAX_QUEUE pieces queued behind it (:meth:`Actuator.set_pieces`): the next takes over at
the first step whose start the one before no longer holds for (:func:`piece_at`, in Python and C
steps alike), so that a trajectory's pieces follow each other without their owner.

A SEGMENT_PID actuator may watch a band (:meth:`Actuator.watch_band`: a trajectory goal's path
tolerances): a native stretch ends before a step whose start state has |e| > position tolerance
or |e_dot| > velocity tolerance, so that the owner's update in Python checks that step (the
pure-Python backend runs every hook at every step; there the owner checks for itself). Both the
watch and the owner's check read the error of the one function per backend
(:func:`tracking_error` here, ``mr_tracking_error`` in C; :meth:`Actuator.tracking_error`).

Model actuators (``World.add_model_actuator``: :class:`ModelActuator`) act on a whole model, before
the joint actuators of each step: :func:`step_model_python` here, ``mr_apply_model_actuators`` in C.

==================  ===================================================================
PLANAR_VELOCITY     command (vx, vy, wz): every body of the model gets the rigid twist of
                    the base link moving at (vx, vy) in its heading (the yaw of its pose
                    at the step's start), vertical velocity 0, turning at wz about z
                    (a planar move plugin's base)
==================  ===================================================================

:class:`Pid` is control_toolbox::Pid (ROS Noetic, control_toolbox 1.18):

* gains ``p`` (required), ``i``, ``d`` (default 0), ``i_max``, ``i_min``, ``antiwindup`` (false);
* ``compute(error, dt)`` takes the error derivative by finite difference; ``compute(error, dt,
  error_dot)`` uses the given one;
* the integral ``i_error`` accumulates ``dt * error``. Without antiwindup the integral TERM is
  clamped to [i_min, i_max] -- so with no i_clamp the integral term is zero, as in ros_control.
  With antiwindup the integral STATE is clamped to [i_min/i, i_max/i];
* dt == 0 or a non-finite error returns 0.
"""
import math
import weakref
from collections import namedtuple

from ..errors import InputError, SimulationError
from .angles import shortest_angular_distance
from .model import FORCE_CAP, check_twist
from .transforms import check_vec3, rpy_from_quat

#: actuator kinds (the numbers are the C loop's)
EFFORT, POSITION_PID, SEGMENT_PID, VELOCITY_PID, MOTOR, FOLLOW_PID = 0, 1, 2, 3, 4, 5
KIND_NAMES = {EFFORT: "EFFORT", POSITION_PID: "POSITION_PID", SEGMENT_PID: "SEGMENT_PID",
              VELOCITY_PID: "VELOCITY_PID", MOTOR: "MOTOR", FOLLOW_PID: "FOLLOW_PID"}
#: what an actuator's output drives: the joint's effort, or its ODE motor's velocity (the numbers
#: are the C loop's)
OUT_EFFORT, OUT_VELOCITY, OUT_POSITION = 0, 1, 2
OUTPUT_NAMES = {OUT_EFFORT: "OUT_EFFORT", OUT_VELOCITY: "OUT_VELOCITY", OUT_POSITION: "OUT_POSITION"}
#: position error rules: target - q; the target clamped to [lower, upper] first; shortest angle
PLAIN, CLAMPED, SHORTEST = 0, 1, 2
#: segment kinds: polynomial in absolute time, in time relative to ``base``, holding a position
ABSOLUTE, RELATIVE, HOLD = 0, 1, 2
MAX_COEFFS = 6
#: the pieces a SEGMENT_PID actuator queues behind its own (Actuator.queue_pieces; the C loop's MR_QUEUE)
MAX_QUEUE = 32
INF = float("inf")

#: model actuator kinds (World.add_model_actuator; numbered apart from the joint kinds)
PLANAR_VELOCITY = 0
MODEL_KIND_NAMES = {PLANAR_VELOCITY: "PLANAR_VELOCITY"}

#: what one step of an actuator did (``Actuator.last``)
ActuatorSample = namedtuple("ActuatorSample", "t position velocity set_point desired_velocity error "
                                              "error_dot p_term i_term d_term output applied")


class PidGains(object):
    __slots__ = ("p", "i", "d", "i_max", "i_min", "antiwindup")

    def __init__(self, p, i=0.0, d=0.0, i_max=0.0, i_min=0.0, antiwindup=False):
        self.p, self.i, self.d = float(p), float(i), float(d)
        self.i_max, self.i_min = float(i_max), float(i_min)
        self.antiwindup = bool(antiwindup)

    def as_dict(self):
        return {"p": self.p, "i": self.i, "d": self.d, "i_clamp_max": self.i_max,
                "i_clamp_min": self.i_min, "antiwindup": self.antiwindup}

    def __repr__(self):
        return "PidGains(p=%g, i=%g, d=%g, i_max=%g, i_min=%g, antiwindup=%s)" % (
            self.p, self.i, self.d, self.i_max, self.i_min, self.antiwindup)


class Pid(object):
    """One PID loop. ``gains`` may be replaced at any time (one reference swap: live tuning)."""

    def __init__(self, gains):
        self.gains = gains
        self.reset()

    def reset(self):
        self.p_error_last = 0.0
        self.p_error = 0.0
        self.i_error = 0.0
        self.d_error = 0.0
        self.cmd = 0.0
        self.terms = (0.0, 0.0, 0.0)

    def set_gains(self, gains):
        self.gains = gains

    def state(self):
        """(p_error_last, p_error, i_error, d_error, cmd)."""
        return (self.p_error_last, self.p_error, self.i_error, self.d_error, self.cmd)

    def compute(self, error, dt, error_dot=None):
        if dt <= 0.0 or not math.isfinite(error):
            return 0.0
        if error_dot is None:
            error_dot = (error - self.p_error_last) / dt
            self.p_error_last = error
        if not math.isfinite(error_dot):
            return 0.0
        g = self.gains
        self.p_error = error
        self.d_error = error_dot
        p_term = g.p * error
        self.i_error += dt * error
        if g.antiwindup and g.i != 0.0:
            lo, hi = sorted((g.i_min / g.i, g.i_max / g.i))
            self.i_error = min(max(self.i_error, lo), hi)
        i_term = g.i * self.i_error
        if not g.antiwindup:
            i_term = min(max(i_term, g.i_min), g.i_max)
        d_term = g.d * error_dot
        self.terms = (p_term, i_term, d_term)
        self.cmd = p_term + i_term + d_term
        return self.cmd


def eval_polynomial(coeffs, s):
    """(position, velocity, acceleration) of sum(c_k s^k) at ``s``."""
    pos = vel = acc = 0.0
    for k, ck in enumerate(coeffs):
        pos += ck * s ** k
        if k >= 1:
            vel += k * ck * s ** (k - 1)
        if k >= 2:
            acc += k * (k - 1) * ck * s ** (k - 2)
    return pos, vel, acc


def segment_time(t, t0, t1):
    """The polynomial's argument at time ``t`` for a segment on [t0, t1] (clamped to it)."""
    return min(max(t, t0), t1) - t0


def position_error(rule, target, q, lower, upper):
    """The error of a position PID: PLAIN target - q, CLAMPED the target clamped to [lower, upper]
    first (a revolute joint's travel), SHORTEST the shortest angle (a continuous joint)."""
    if rule == SHORTEST:
        return shortest_angular_distance(q, target)
    if rule == CLAMPED:
        return min(max(target, lower), upper) - q
    return target - q


class PyRecord(object):
    """An actuator's data on the pure-Python backend (the native backend's is the C struct
    MrActuator with the same field names; the PID's state is ``pid`` here)."""
    __slots__ = ("kind", "err_kind", "has_hw_limit", "has_extra", "lower", "upper", "hw_limit", "command",
                 "extra", "t", "position", "velocity", "set_point", "desired_velocity", "out", "applied",
                 "traj_kind", "coef", "seg_t0", "seg_t1", "rel_base", "offset", "has_offset", "ff",
                 "abs_until", "rel_until", "max_force", "accel", "motor_vel", "out_kind", "vel_limit",
                 "bodies", "pos_prev", "watch", "watch_target", "watch_tol", "watch_vel", "watch_timeout",
                 "moved_at", "master", "mult", "follow_offset", "deadband", "has_follow_vel", "follow_vel",
                 "bias", "master_position", "band", "band_pos", "band_vel", "queue", "qnext", "pid")

    def __init__(self, kind):
        self.kind = kind
        self.err_kind = PLAIN
        self.has_hw_limit = 0
        self.has_extra = 0
        self.lower = self.upper = self.hw_limit = 0.0
        self.command = self.extra = 0.0
        self.t = self.position = self.velocity = self.set_point = self.desired_velocity = 0.0
        self.out = self.applied = 0.0
        self.traj_kind = HOLD
        self.coef = [0.0]
        self.seg_t0 = self.seg_t1 = self.rel_base = self.offset = self.ff = 0.0
        self.has_offset = 0
        self.abs_until = self.rel_until = INF
        self.max_force = self.accel = self.motor_vel = 0.0
        self.out_kind = OUT_EFFORT
        self.vel_limit = INF
        self.bodies = ()
        self.pos_prev = 0.0
        self.watch = 0
        self.watch_target = self.watch_tol = self.watch_vel = self.watch_timeout = self.moved_at = 0.0
        self.master = None          # FOLLOW_PID: the Joint followed (the C record: its ODE joint)
        self.mult, self.follow_offset, self.deadband = 1.0, 0.0, 0.0
        self.has_follow_vel = 0     # FOLLOW_PID: the derivative is follow_vel - dq (else the error's change)
        self.follow_vel = self.bias = 0.0
        self.master_position = 0.0  # FOLLOW_PID: the master's position at the step's start
        self.band = 0
        self.band_pos = self.band_vel = 0.0
        self.queue = []             # SEGMENT_PID: the pieces queued behind its own (piece_at)
        self.qnext = 0
        self.pid = Pid(PidGains(0.0))


def segment_piece(coeffs, t0, t1, base=None, offset=None, until=INF, rel_until=INF):
    """A SEGMENT_PID piece (Actuator.set_segment's arguments; a record's fields of the same
    names: traj_kind, coef, has_offset, seg_t0, seg_t1, rel_base, offset, abs_until, rel_until)."""
    n = len(coeffs)
    if not 1 <= n <= MAX_COEFFS:
        raise ValueError("a segment has 1 to %d coefficients, got %d" % (MAX_COEFFS, n))
    return (ABSOLUTE if base is None else RELATIVE, [float(c) for c in coeffs], 0 if offset is None else 1,
            float(t0), float(t1), 0.0 if base is None else float(base),
            0.0 if offset is None else float(offset), float(until), float(rel_until))


def hold_piece(position, until=INF):
    """A SEGMENT_PID piece that holds ``position`` (velocity 0) for steps starting before ``until``."""
    return (HOLD, [float(position)], 0, 0.0, 0.0, 0.0, 0.0, float(until), INF)


def piece_holds(r, t):
    """Whether the record's piece holds for a step starting at ``t`` (trajectory.Piece's tests)."""
    return t < r.abs_until and t - r.rel_base < r.rel_until


def piece_at(r, t):
    """The queued pieces of the SEGMENT_PID record ``r`` take over, in order, while its piece does
    not hold for a step starting at ``t`` (the C loop's mr_piece_at)."""
    queue = r.queue
    while r.qnext < len(queue) and not piece_holds(r, t):
        r.coef = list(put_piece(r, queue[r.qnext]))
        r.qnext += 1


def put_piece(r, piece):
    """The record's piece := ``piece`` (segment_piece, hold_piece), but for its coefficients, which
    are returned (the backend's record keeps them its own way)."""
    (r.traj_kind, coef, r.has_offset, r.seg_t0, r.seg_t1, r.rel_base, r.offset, r.abs_until,
     r.rel_until) = piece
    return coef


def segment_sample(r, t):
    """(desired position, desired velocity) of a SEGMENT_PID record at ``t``."""
    if r.traj_kind == HOLD:
        return r.coef[0], 0.0
    tt = t - r.rel_base if r.traj_kind == RELATIVE else t
    pos, vel, _acc = eval_polynomial(r.coef, segment_time(tt, r.seg_t0, r.seg_t1))
    return (pos + r.offset if r.has_offset else pos), vel


def tracking_error(rule, desired, desired_velocity, q, v):
    """(position error, velocity error) of a joint at (q, v) against the desired (position,
    velocity): desired - q (SHORTEST: the shortest angle from q to desired) and
    desired_velocity - v (a SEGMENT_PID's PID input; a trajectory controller's state error)."""
    e = shortest_angular_distance(q, desired) if rule == SHORTEST else desired - q
    return e, desired_velocity - v


def saturate_position(rule, prev, target, vel_limit, dt, lower, upper):
    """joint_limits_interface::PositionJointSaturationHandle on a position command: SHORTEST (a
    continuous joint) the short way from ``prev``; at most ``vel_limit * dt`` from ``prev`` (the
    last command); otherwise into [lower, upper]."""
    if rule == SHORTEST:
        target = prev + shortest_angular_distance(prev, target)
    if vel_limit < INF and dt > 0.0:
        step = vel_limit * dt
        target = min(max(target, prev - step), prev + step)
    if rule != SHORTEST:
        target = min(max(target, lower), upper)
    return target


def place_subtree(joint, bodies, delta):
    """Turn (a prismatic joint: slide) the ODE ``bodies`` below ``joint`` rigidly about its axis by
    ``delta``; then each moves with the joint's parent body (at rest without one): the joint is
    at its position + delta with velocity 0 (OUT_POSITION; the C loop's mr_place_subtree)."""
    oj = joint.ode_joint
    parent = oj.getBody(1)
    angular = joint.is_angular
    ax = oj.getAxis()
    if angular:
        a = oj.getAnchor()
        h = 0.5 * delta
        sh = math.sin(h)
        qx, qy, qz, qw = ax[0] * sh, ax[1] * sh, ax[2] * sh, math.cos(h)
    for b in bodies:
        p = b.getPosition()
        if angular:
            rx, ry, rz = p[0] - a[0], p[1] - a[1], p[2] - a[2]
            tx = 2.0 * (qy * rz - qz * ry)
            ty = 2.0 * (qz * rx - qx * rz)
            tz = 2.0 * (qx * ry - qy * rx)
            n = (a[0] + (rx + qw * tx + (qy * tz - qz * ty)),
                 a[1] + (ry + qw * ty + (qz * tx - qx * tz)),
                 a[2] + (rz + qw * tz + (qx * ty - qy * tx)))
            o = b.getQuaternion()                  # w x y z
            b.setPosition(n)
            b.setQuaternion((qw * o[0] - qx * o[1] - qy * o[2] - qz * o[3],
                             qw * o[1] + qx * o[0] + qy * o[3] - qz * o[2],
                             qw * o[2] + qy * o[0] + qz * o[1] - qx * o[3],
                             qw * o[3] + qz * o[0] + qx * o[2] - qy * o[1]))
        else:
            n = (p[0] + ax[0] * delta, p[1] + ax[1] * delta, p[2] + ax[2] * delta)
            b.setPosition(n)
        if parent is None:
            b.setLinearVel((0.0, 0.0, 0.0))
            b.setAngularVel((0.0, 0.0, 0.0))
        else:
            pv, pw, pp = parent.getLinearVel(), parent.getAngularVel(), parent.getPosition()
            rx, ry, rz = n[0] - pp[0], n[1] - pp[1], n[2] - pp[2]
            b.setLinearVel((pv[0] + (pw[1] * rz - pw[2] * ry), pv[1] + (pw[2] * rx - pw[0] * rz),
                            pv[2] + (pw[0] * ry - pw[1] * rx)))
            b.setAngularVel(pw)


def apply_python(actuated, t, dt):
    """One step of every actuator in ``actuated``, pairs (record, physics Joint): each reads its
    joint's state (:func:`read_python`), then each acts (:func:`step_python`), so that no actuator
    sees what another did in the step."""
    for r, joint in actuated:
        read_python(r, joint, t)
    for r, joint in actuated:
        step_python(r, joint, dt, joint.limit_effort)


def read_python(r, joint, t):
    """The state the actuator ``r`` (a PyRecord) works from in the step that starts at ``t``: its
    joint's position and velocity, a FOLLOW_PID's master's position."""
    r.t, r.position, r.velocity = t, joint.position, joint.velocity
    if r.kind == SEGMENT_PID:
        piece_at(r, t)
    if r.kind == FOLLOW_PID and r.master is not None:
        r.master_position = r.master.position


def step_python(r, joint, dt, limit):
    """One step of the actuator ``r`` (a PyRecord) on the physics Joint ``joint``: its output from
    the state :func:`read_python` read, applied through the joint's ODE joint (an effort, or the
    motor's velocity); ``limit(f)`` is the joint's own clamp (Joint.limit_effort). Returns the
    effort applied (MOTOR: None, the motor acts)."""
    t, q, v = r.t, r.position, r.velocity
    kind = r.kind
    pid = r.pid
    if r.out_kind == OUT_POSITION:
        if kind == SEGMENT_PID:
            target, r.desired_velocity = segment_sample(r, t)
        else:
            target = r.command
            r.desired_velocity = 0.0
        r.set_point = target
        if not math.isfinite(target):
            target = r.pos_prev
        target = saturate_position(r.err_kind, r.pos_prev, target, r.vel_limit, dt, r.lower, r.upper)
        r.pos_prev = r.out = target
        place_subtree(joint, r.bodies, target - q)
        joint.turned_to(target)
        return _apply_effort(r, joint, 0.0, limit)
    if kind == POSITION_PID:
        r.set_point = target = r.command
        r.desired_velocity = 0.0
        f = pid.compute(position_error(r.err_kind, target, q, r.lower, r.upper), dt)
    elif kind == SEGMENT_PID:
        dpos, dvel = segment_sample(r, t)
        r.set_point, r.desired_velocity = dpos, dvel
        error, error_dot = tracking_error(r.err_kind, dpos, dvel, q, v)
        f = pid.compute(error, dt, error_dot) + r.ff * dvel
    elif kind == VELOCITY_PID:
        r.set_point = r.command
        r.desired_velocity = r.command
        f = pid.compute(r.command - v, dt)
    elif kind == MOTOR:
        target = r.command
        if r.accel > 0.0:
            step = r.accel * dt
            target = min(max(target, r.motor_vel - step), r.motor_vel + step)
        r.motor_vel = target
        r.set_point = r.desired_velocity = target
        r.out = 0.0
        joint.drive_motor(target, r.max_force)
        return None
    elif kind == FOLLOW_PID:
        r.desired_velocity = r.follow_vel if r.has_follow_vel else 0.0
        if r.master is None:
            r.set_point = q
            f = 0.0
        else:
            r.set_point = target = r.mult * r.master_position + r.follow_offset
            error = target - q
            if abs(error) < r.deadband:
                f = 0.0
            elif r.has_follow_vel:
                f = pid.compute(error, dt, r.follow_vel - v)
            else:
                f = pid.compute(error, dt)
            f += r.bias
    else:
        f = r.set_point = r.command
        r.desired_velocity = 0.0
    r.out = f
    if not math.isfinite(f):
        f = 0.0
    if r.out_kind == OUT_VELOCITY:
        joint.drive_motor(min(max(f, -r.vel_limit), r.vel_limit), r.max_force)
        f = 0.0
    elif r.has_hw_limit:
        f = min(max(f, -r.hw_limit), r.hw_limit)
    return _apply_effort(r, joint, f, limit)


def _apply_effort(r, joint, f, limit):
    """The effort ``f`` plus the efforts given with set_effort for this step, through the joint's
    clamp ``limit``, to the joint."""
    if r.has_extra:
        f += r.extra
        r.has_extra = 0
        r.extra = 0.0
    f = limit(f)
    joint.add_raw_effort(f)
    r.applied = f
    return f


class Actuator(object):
    """The handle of one actuator (``world.add_actuator``). Use it from the simulation loop thread
    only (set-points, gains, segments), like the World itself."""

    def __init__(self, world, backend, joint, kind, record):
        # the World only weakly (as models hold it): its finalizer must run before the cycle
        # collector frees PyODE objects in an arbitrary order
        self._world = weakref.ref(world) if world is not None else None
        # the backend weakly too: its tables lead to the models and back to the joint this drives
        # (joint.actuator), a cycle that only the cycle collector would free
        self._backend = weakref.ref(backend)
        self.joint = joint
        self._r = record
        self._kind = kind
        self._master = None

    def __repr__(self):
        return "<Actuator %s on %s::%s>" % (KIND_NAMES.get(self._kind, self._kind), self.joint.model.name,
                                            self.joint.name)

    @property
    def record(self):
        """The backend's data of this actuator (physics side: the World's backends)."""
        return self._r

    @property
    def _be(self):
        be = self._backend()
        if be is None:
            raise SimulationError("%r: its World is gone (closed or dropped); make a new actuator with "
                                  "world.add_actuator in the World that runs now" % self)
        return be

    @property
    def kind(self):
        return self._kind

    @kind.setter
    def kind(self, kind):
        """Switch kind (a controller taking the joint over); the PID state starts from zero."""
        if kind not in KIND_NAMES:
            raise ValueError("unknown actuator kind %r (known: %s)" % (kind, ", ".join(KIND_NAMES.values())))
        motor = self.drives_motor
        self._kind = kind
        self._r.kind = kind
        self._r.band = 0
        self._be.set_actuator_queue(self._r, ())
        self._pieces_end = INF
        if self._r.out_kind == OUT_POSITION and kind not in (EFFORT, POSITION_PID, SEGMENT_PID):
            self._r.out_kind = OUT_EFFORT       # a kind without a set-point drives the effort
        if motor and not self.drives_motor:
            self.joint.release_motor()
        if kind == MOTOR:
            self._r.motor_vel = self.joint.velocity
        self.reset()

    @property
    def command(self):
        return self._r.command

    @command.setter
    def command(self, value):
        self._r.command = float(value)

    @property
    def error(self):
        return self._r.err_kind

    @error.setter
    def error(self, rule):
        if rule not in (PLAIN, CLAMPED, SHORTEST):
            raise ValueError("actuator error rule must be PLAIN, CLAMPED or SHORTEST, got %r" % (rule,))
        r = self._r
        r.err_kind = rule
        j = self.joint
        r.lower = j.lower if j.lower is not None else -INF
        r.upper = j.upper if j.upper is not None else INF

    @property
    def effort_limit(self):
        return self._r.hw_limit if self._r.has_hw_limit else None

    @effort_limit.setter
    def effort_limit(self, limit):
        self._r.has_hw_limit = 0 if limit is None else 1
        self._r.hw_limit = 0.0 if limit is None else float(limit)

    @property
    def output(self):
        return self._r.out_kind

    @output.setter
    def output(self, output):
        """OUT_EFFORT or OUT_VELOCITY (what the kind's output drives; MOTOR always drives the
        motor). Leaving OUT_VELOCITY gives the joint its own motor back (its friction)."""
        if output not in OUTPUT_NAMES:
            raise ValueError("actuator output must be OUT_EFFORT, OUT_VELOCITY or OUT_POSITION, got %r"
                             % (output,))
        if output == OUT_POSITION and self._kind not in (EFFORT, POSITION_PID, SEGMENT_PID):
            raise ValueError("an OUT_POSITION actuator takes its set-point from an EFFORT, POSITION_PID or "
                             "SEGMENT_PID kind, not %s" % KIND_NAMES[self._kind])
        r = self._r
        was = r.out_kind
        if output == OUT_POSITION and was != OUT_POSITION:
            j = self.joint
            self._be.set_actuator_bodies(r, j.model.subtree_bodies(j))
            r.lower = j.lower if j.lower is not None else -INF
            r.upper = j.upper if j.upper is not None else INF
            self.hold_position()
        r.out_kind = output
        if was == OUT_VELOCITY and output != OUT_VELOCITY and self._kind != MOTOR:
            self.joint.release_motor()

    def follow(self, master, multiplier=1.0, offset=0.0, deadband=0.0, velocity=None, bias=0.0):
        """FOLLOW_PID: the set-point is ``multiplier * master.position + offset`` at every step
        (``master``: a revolute, continuous or prismatic joint of the same model, or the actuator's
        own joint: a set-point ``offset`` away from where it is; None: none, no effort); an error
        below ``deadband`` gives no PID effort and leaves the PID as it is. The PID's derivative is
        the error's change, or with ``velocity`` (a number) ``velocity`` - the joint's velocity;
        ``bias`` is an effort added to the PID's (before the clamps)."""
        j = self.joint
        what = "%r: follow(%r)" % (self, master)
        if master is not None:
            if getattr(master, "model", None) is not j.model:
                raise InputError("%s: the master must be a joint of model '%s'" % (what, j.model.name))
            if master.ode_joint is None or master.type not in ("revolute", "continuous", "prismatic"):
                raise InputError("%s: joint '%s' is %s; only a revolute, continuous or prismatic joint "
                                 "can be followed" % (what, master.name, master.type))
        try:
            m, o, d, b = float(multiplier), float(offset), float(deadband), float(bias)
            v = None if velocity is None else float(velocity)
        except (TypeError, ValueError):
            raise InputError("%s: multiplier, offset, deadband, velocity and bias must be numbers" % what)
        if not (math.isfinite(m) and math.isfinite(o) and math.isfinite(b) and d >= 0.0
                and (v is None or math.isfinite(v))):
            raise InputError("%s: multiplier %r, offset %r, velocity %r and bias %r must be finite, "
                             "deadband %r >= 0" % (what, multiplier, offset, velocity, bias, deadband))
        r = self._r
        r.mult, r.follow_offset, r.deadband, r.bias = m, o, d, b
        r.has_follow_vel = 0 if v is None else 1
        r.follow_vel = 0.0 if v is None else v
        self._master = master
        self._be.set_actuator_master(r, master)

    @property
    def master(self):
        """FOLLOW_PID: the joint followed (None: none)."""
        return self._master

    def watch(self, target, tolerance, still_velocity, timeout, moved_at):
        """A goal's checks for the native stretches (a gripper goal): a stretch ends before a step
        whose start state has |target - position| < tolerance, or |velocity| <= still_velocity
        while the joint has not moved faster since ``timeout`` (``moved_at``: when it last did;
        :attr:`moved_at` then follows the stretches' steps). The pure-Python backend steps every
        hook at every step, so there the owner checks for itself."""
        r = self._r
        r.watch_target, r.watch_tol = float(target), float(tolerance)
        r.watch_vel, r.watch_timeout, r.moved_at = float(still_velocity), float(timeout), float(moved_at)
        r.watch = 1

    def unwatch(self):
        self._r.watch = 0

    @property
    def watching(self):
        return bool(self._r.watch)

    @property
    def moved_at(self):
        """The last step start (of a native stretch) at which the watched joint moved faster than
        its still velocity."""
        return self._r.moved_at

    def watch_band(self, position, velocity=0.0):
        """SEGMENT_PID: a native stretch ends before a step whose start state has a tracking error
        (:meth:`tracking_error`) with |error| > ``position`` or |error_dot| > ``velocity`` (a
        tolerance of 0 is not checked; both 0: no band), so that the owner's update runs in Python
        at that step (a trajectory goal's path tolerances, which ros_controllers checks at every
        update). The pure-Python backend steps every hook at every step: there the owner checks
        for itself. Switching the kind ends the band."""
        if self._kind != SEGMENT_PID:
            raise ValueError("%r: a band watches a SEGMENT_PID actuator's tracking error; this one is %s"
                             % (self, KIND_NAMES[self._kind]))
        try:
            p, v = float(position), float(velocity)
        except (TypeError, ValueError):
            raise InputError("%r: watch_band(%r, %r): the tolerances must be numbers"
                             % (self, position, velocity))
        if not (p >= 0.0 and v >= 0.0 and math.isfinite(p) and math.isfinite(v)):
            raise InputError("%r: watch_band(%r, %r): the tolerances must be finite and >= 0 (0: not checked)"
                             % (self, position, velocity))
        r = self._r
        r.band_pos, r.band_vel = p, v
        r.band = 1 if (p > 0.0 or v > 0.0) else 0

    def unwatch_band(self):
        self._r.band = 0

    @property
    def band(self):
        """(position, velocity) tolerances of the band watched, or None."""
        r = self._r
        return (r.band_pos, r.band_vel) if r.band else None

    def tracking_error(self, t):
        """SEGMENT_PID: (error, error_dot) of the segment's desired state at ``t`` against the
        joint's state now, computed by the backend as its step at ``t`` computes them (so a
        controller's check and the band agree to the last bit)."""
        if self._kind != SEGMENT_PID:
            raise ValueError("%r: only a SEGMENT_PID actuator has a tracking error; this one is %s"
                             % (self, KIND_NAMES[self._kind]))
        return self._be.actuator_tracking_error(self._r, self.joint, float(t))

    def hold_position(self):
        """OUT_POSITION: the set-point saturation starts from the joint's position now (a
        controller's first command, the hardware's reset)."""
        self._r.pos_prev = self.joint.position

    @property
    def velocity_limit(self):
        """OUT_VELOCITY: the velocity is clamped to +-velocity_limit; OUT_POSITION: the set-point
        moves at most velocity_limit * dt per step (None: neither)."""
        v = self._r.vel_limit
        return None if v == INF else v

    @velocity_limit.setter
    def velocity_limit(self, limit):
        self._r.vel_limit = INF if limit is None else abs(float(limit))

    @property
    def drives_motor(self):
        """True when the actuator sets the joint's ODE motor (MOTOR, or OUT_VELOCITY)."""
        return self._kind == MOTOR or self._r.out_kind == OUT_VELOCITY

    @property
    def feedforward(self):
        return self._r.ff

    @feedforward.setter
    def feedforward(self, ff):
        self._r.ff = float(ff)

    @property
    def max_force(self):
        return self._r.max_force

    @max_force.setter
    def max_force(self, f):
        """The motor's force bound (MOTOR, OUT_VELOCITY): at most FORCE_CAP, as for every force."""
        self._r.max_force = min(float(f), FORCE_CAP)

    @property
    def acceleration(self):
        return self._r.accel

    @acceleration.setter
    def acceleration(self, a):
        self._r.accel = float(a)

    def set_segment(self, coeffs, t0, t1, base=None, offset=None, until=INF, rel_until=INF):
        """SEGMENT_PID: the desired state from now on is the polynomial ``coeffs`` on [t0, t1] in
        absolute time (``base`` None) or in time relative to ``base``, plus ``offset`` (None: no
        offset); valid for steps starting at t < ``until`` with t - base < ``rel_until`` (then the
        next piece queued takes over, or without one the World steps in Python, and the owner
        places the next segment). Nothing stays queued."""
        self.set_pieces([segment_piece(coeffs, t0, t1, base, offset, until, rel_until)])

    def hold(self, position, until=INF):
        """SEGMENT_PID: desired position ``position``, velocity 0; nothing stays queued."""
        self.set_pieces([hold_piece(position, until)])

    def set_pieces(self, pieces):
        """SEGMENT_PID: the desired state from now on is the first of ``pieces`` (segment_piece,
        hold_piece), and the others follow it in order, at most MAX_QUEUE of them: at the first
        step whose start the actuator's piece no longer holds for, the next one that does takes
        over (natively and in Python steps alike, :func:`piece_at`), so that a trajectory's pieces
        follow each other without their owner; a native stretch ends before a step that the last
        one no longer holds for."""
        if not pieces:
            raise ValueError("%r: set_pieces needs at least one piece" % self)
        if len(pieces) > MAX_QUEUE + 1:
            raise ValueError("%r: at most %d pieces at once (one and %d queued), got %d"
                             % (self, MAX_QUEUE + 1, MAX_QUEUE, len(pieces)))
        r = self._r
        self._be.set_actuator_coeffs(r, put_piece(r, pieces[0]))
        self._be.set_actuator_queue(r, pieces[1:])
        last = pieces[-1]
        self._pieces_end = min(last[7], last[5] + last[8]) if last[0] == RELATIVE else last[7]

    _pieces_end = INF

    def segment_ends(self):
        """The time from which the last piece set (set_pieces) no longer holds, about (SEGMENT_PID;
        else inf; a relative piece's end in absolute time, rounded)."""
        return self._pieces_end if self._kind == SEGMENT_PID else INF

    @property
    def gains(self):
        return self._be.actuator_gains(self._r)

    @gains.setter
    def gains(self, gains):
        self._be.set_actuator_gains(self._r, gains)

    def reset(self):
        """PID state to zero (a controller's starting())."""
        self._be.reset_actuator_pid(self._r)

    def pid_state(self):
        """(p_error_last, p_error, i_error, d_error, cmd) of the PID."""
        return self._be.actuator_pid_state(self._r)

    @property
    def last(self):
        """ActuatorSample of the last step the actuator ran."""
        r = self._r
        p_error, d_error, p_term, i_term, d_term = self._be.actuator_terms(r)
        return ActuatorSample(r.t, r.position, r.velocity, r.set_point, r.desired_velocity, p_error, d_error,
                              p_term, i_term, d_term, r.out, r.applied)

    @property
    def applied(self):
        return self._r.applied

    def add_extra(self, raw):
        """Efforts given with set_effort/add_effort for this step (World: added before the joint's
        clamp, as Gazebo adds SetForce calls)."""
        r = self._r
        r.extra = (r.extra if r.has_extra else 0.0) + raw
        r.has_extra = 1

    def remove(self):
        world = self._world() if self._world is not None else None
        if world is not None:
            world.remove_actuator(self)


class PyModelRecord(object):
    """A model actuator's data on the pure-Python backend (the native backend's is the C struct
    MrModelActuator with the same command fields)."""
    __slots__ = ("kind", "vx", "vy", "wz")

    def __init__(self, kind):
        self.kind = kind
        self.vx = self.vy = self.wz = 0.0


def step_model_python(r, model):
    """One step of the model actuator ``r`` (a PyModelRecord) on ``model``, before the physics."""
    yaw = rpy_from_quat(model.pose[1])[2]
    c, s = math.cos(yaw), math.sin(yaw)
    model.apply_twist((r.vx * c - r.vy * s, r.vy * c + r.vx * s, 0.0), (0.0, 0.0, r.wz))


class ModelActuator(object):
    """The handle of one model actuator (``world.add_model_actuator``); loop thread only."""

    def __init__(self, world, model, kind, record):
        self._world = weakref.ref(world)
        self.model = model
        self._kind = kind
        self._r = record

    def __repr__(self):
        return "<ModelActuator %s on %s>" % (MODEL_KIND_NAMES.get(self._kind, self._kind), self.model.name)

    @property
    def kind(self):
        return self._kind

    @property
    def record(self):
        """The backend's data of this actuator (physics side: the World's backends)."""
        return self._r

    @property
    def command(self):
        """PLANAR_VELOCITY: (vx, vy, wz), m/s in the base's heading and rad/s about z."""
        r = self._r
        return (r.vx, r.vy, r.wz)

    @command.setter
    def command(self, value):
        what = "%r command" % self
        vx, vy, wz = check_vec3(value, what)
        check_twist((vx, vy, 0.0), (0.0, 0.0, wz), what)
        r = self._r
        r.vx, r.vy, r.wz = vx, vy, wz

    def remove(self):
        world = self._world()
        if world is not None:
            world.remove_model_actuator(self)
