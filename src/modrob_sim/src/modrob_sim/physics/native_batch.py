"""Several World steps in one call into the C loop (``mr_run_batch`` of native/modrob_ode_native.c),
for the stretches in which no Python step hook is due.

A World step in Python costs more than the physics itself once a node hangs its hooks on it
(ros_control's read -> controllers -> write, the publishers' schedules). The /gazebo node knows
when its hooks have something to do: for the steps in between, :meth:`Batcher.run` steps in C,
with the ros_control effort joints (:class:`BatchJoint`, filled by
``modrob_sim.ros_control.native_control``) updated natively at every step. The semantics are the
Python step's (World._step_once), which stays the reference and runs every step that needs
anything else; the C loop ends a batch where the World's guard has to look (a flagged step, a
snapshot step) and this module runs the guard for that step.

Only for worlds whose steps need nothing but the joints' efforts, damping, collide + quickStep and
the guard: no mimic joints, soft limits, wrenches, anti-gravity groups,
frozen models or queued efforts (:meth:`Batcher.eligible`); joints that count turns count them
in C as Joint.track_turns does.
"""
import ctypes

from . import native as native_mod
from . import odelib
from .model import FORCE_CAP

INF = float("inf")


class BatchJoint(ctypes.Structure):
    """One effort joint of the batch (MrBatchJoint). mode 0: constant effort ``command``; mode 1:
    PID on the position error towards ``command`` (err_kind 0 plain, 1 target clamped to
    [lower, upper], 2 shortest angle)."""
    _fields_ = [("joint", ctypes.c_void_p), ("slider", ctypes.c_int), ("mode", ctypes.c_int),
                ("err_kind", ctypes.c_int), ("has_hw_limit", ctypes.c_int), ("antiwindup", ctypes.c_int),
                ("turn", ctypes.c_int)] + \
        [(n, ctypes.c_double) for n in (
            "lower", "upper", "hw_limit", "joint_limit", "force_cap", "command",
            "p", "i", "d", "i_max", "i_min",
            "p_error_last", "p_error", "i_error", "d_error", "cmd", "p_term", "i_term", "d_term",
            "position", "velocity", "effort", "out", "applied")]


class _Turn(ctypes.Structure):
    _fields_ = [("joint", ctypes.c_void_p), ("last_raw", ctypes.c_double), ("turns", ctypes.c_longlong)]


class _Batch(ctypes.Structure):
    _fields_ = [("joints", ctypes.POINTER(BatchJoint)), ("njoints", ctypes.c_int), ("ndamp", ctypes.c_int),
                ("damp_joints", ctypes.c_void_p), ("damp_kinds", ctypes.c_void_p),
                ("damp_coef", ctypes.c_void_p), ("bodies", ctypes.c_void_p), ("nbodies", ctypes.c_int),
                ("nturns", ctypes.c_int), ("turns", ctypes.POINTER(_Turn)),
                ("guard_max_contacts", ctypes.c_int), ("max_contacts", ctypes.c_int),
                ("snapshot_interval", ctypes.c_int)] + \
        [(n, ctypes.c_double)
         for n in ("vmax2", "wmax2", "dt", "gx", "gy", "gz", "layer", "time", "last_start")] + \
        [("iterations", ctypes.c_longlong), ("before_due", ctypes.c_double), ("after_due", ctypes.c_double),
         ("publish", ctypes.c_void_p), ("clock_handle", ctypes.c_void_p), ("clock_period", ctypes.c_double),
         ("last_clock", ctypes.c_double), ("ncontacts", ctypes.c_int),
         ("guard", ctypes.c_int), ("world_step", ctypes.c_int), ("first_bad", ctypes.c_int),
         ("after", ctypes.c_int), ("stop_due", ctypes.c_double), ("clock_sent", ctypes.c_int)]


def _declare(lib):
    if lib is None or not hasattr(lib, "mr_run_batch"):
        return None
    f = lib.mr_run_batch
    f.restype = ctypes.c_int
    f.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Batch), ctypes.c_int]
    return f


_RUN = _declare(native_mod.LIB)


def available(world):
    """True when ``world`` is stepped by the C loop and the loop has mr_run_batch."""
    return _RUN is not None and getattr(world, "native", False) is True


def joint_fields(joint):
    """(ODE joint pointer, slider, joint limit) of a physics Joint for a BatchJoint."""
    lim = joint.effort_limit
    return (odelib.raw_pointer(joint.ode_joint), 0 if joint.is_angular else 1,
            float(lim) if lim is not None and lim > 0.0 else 0.0)


def new_joints(n):
    arr = (BatchJoint * max(1, n))()
    for k in range(n):
        arr[k].force_cap = FORCE_CAP
        arr[k].turn = -1
    return arr


class Batcher(object):
    """Runs batches of steps of ``world`` (native backend only)."""

    def __init__(self, world):
        self.world = world
        self._b = _Batch()
        self._ref = ctypes.byref(self._b)
        self._turn_src = (None, None)   # (the World's turn-tracking joints, the joint array)
        self.last_start = 0.0
        self.after_due = False
        self._turns = None

    def eligible(self):
        w = self.world
        return (w.native and not w._mimics and not w._soft and not w._wrench_links
                and not w._anti_gravity and not w._frozen and not w._effort_joints)

    def run(self, n, joints, njoints, physics_joints, before_due, after_due, clock=None, stop_due=INF):
        """Up to ``n`` steps in C; returns the number done (0: the first step is due for Python).
        A step whose after-hooks are due (it ends at t with t + 1e-12 >= ``after_due``) ends the
        batch with ``after_due`` set: the caller then runs :meth:`run_after_hooks`.
        ``joints``: a BatchJoint array of ``njoints`` entries for the physics Joints
        ``physics_joints`` (same order), ``clock``: an object with ``publish`` (function pointer),
        ``handle``, ``period`` (0: every step, else at most once per ``period`` s of
        time.monotonic) and ``last`` (time.monotonic of the last /clock, updated) to publish
        /clock after the steps (``sent`` set True when it went out after the last one), or None.
        The caller makes sure that no before-hook is due at a step starting before
        ``before_due`` within these n steps, and no after-hook at a step ending (+ 1e-12) before
        ``after_due``. A step starting at t >= ``stop_due`` ends the batch once
        made (the caller then does with what that step read what was due at its start)."""
        w = self.world
        be = w._backend
        b = self._b
        dt = w._dt
        ndamp, dj, dk, dc, bodies, nbodies = be.batch_arrays()
        b.joints = joints
        b.njoints = njoints
        b.ndamp = ndamp
        b.damp_joints = ctypes.addressof(dj)
        b.damp_kinds = ctypes.addressof(dk)
        b.damp_coef = ctypes.addressof(dc)
        b.bodies = ctypes.addressof(bodies)
        b.nbodies = nbodies
        b.guard_max_contacts = int(w._params["guard_max_contacts"])
        b.max_contacts = int(w._max_contacts)
        b.snapshot_interval = int(w._params["snapshot_interval"])
        b.vmax2, b.wmax2 = w._vmax2, w._wmax2
        b.dt = dt
        b.gx, b.gy, b.gz = w.gravity
        b.layer = w._layer
        b.world_step = 1 if w._world_step else 0
        b.time = w.time
        b.iterations = w.iterations
        b.before_due = before_due
        b.after_due = after_due
        b.stop_due = stop_due
        if clock is not None:
            b.publish, b.clock_handle, b.clock_period, b.last_clock = (clock.publish, clock.handle,
                                                                       clock.period, clock.last)
        else:
            b.publish, b.clock_handle = None, None
        unwrap = w._unwrap
        if self._turn_src[0] is not unwrap or self._turn_src[1] is not joints:
            self._turn_src = (unwrap, joints)
            self._turns = (_Turn * max(1, len(unwrap)))()
            index = {}
            for u, j in enumerate(unwrap):
                self._turns[u].joint = odelib.raw_pointer(j.ode_joint)
                index[id(j)] = u
            for idx, j in enumerate(physics_joints):
                joints[idx].turn = index.get(id(j), -1)
        turns = self._turns
        for u, j in enumerate(unwrap):
            turns[u].turns, turns[u].last_raw = j.turn_state
        b.turns = turns
        b.nturns = len(unwrap)
        k = _RUN(be.ctx, self._ref, int(n))
        if k <= 0:
            return 0
        w.time = b.time
        w.iterations = b.iterations
        for u, j in enumerate(unwrap):
            j.turn_state = (turns[u].turns, turns[u].last_raw)
        # what the first step's World._apply_forces did to efforts of the step before that were
        # not commanded again (the batch joints were, at every step: set below)
        for j in w._last_effort_joints:
            j.effort = 0.0
        if clock is not None:
            clock.last = b.last_clock
            clock.sent = bool(b.clock_sent)
        w._ncontacts = b.ncontacts
        be.batch_done(b.ncontacts, b.first_bad)
        for idx, j in enumerate(physics_joints):
            j.effort = joints[idx].applied
        w._last_effort_joints = list(physics_joints)
        self.last_start = b.last_start
        self.after_due = bool(b.after)
        if b.guard:
            w._guard()
            if w._frozen:
                w._hold_frozen()
        return k

    def run_after_hooks(self):
        """The World's after-step hooks for the last step of the batch (when ``after_due``: the
        batch made that step because only its after-hooks needed Python)."""
        w = self.world
        t, dt = w.time, w._dt
        for h in w._after:
            h(t, dt)
