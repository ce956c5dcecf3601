"""Several World steps in one call into the C loop (``mr_run_batch`` of native/modrob_ode_native.c),
for the stretches in which no Python step hook is due.

A World step in Python costs more than the physics itself once a node hangs its hooks on it
(ros_control's read -> controllers -> write, the publishers' schedules). The /gazebo node knows
when its hooks have something to do: for the steps in between, :meth:`Batcher.run` steps in C,
with the World's actuators (physics.actuators) run natively at every step. The semantics are the
Python step's (World._step_once), which stays the reference and runs every step that needs
anything else; the C loop ends a batch where the World's guard has to look (a flagged step, a
snapshot step) and this module runs the guard for that step.

Only for worlds whose steps need nothing but the joints' efforts, damping, mimic couplings, soft
limits, collide + quickStep and the guard: no wrenches, anti-gravity groups, frozen models or
queued efforts (:meth:`Batcher.eligible`); joints that count turns count them in C as
Joint.track_turns does, mimic joints are driven as Joint.drive_mimic and soft limits moved as
Joint.update_soft_limits does it.
"""
import ctypes

from . import native as native_mod
from . import odelib
from .backends import MrTurn
from .model import MIMIC_COUPLING_FORCE, MIMIC_GAIN

INF = float("inf")


class _Mimic(ctypes.Structure):
    _fields_ = [("joint", ctypes.c_void_p), ("master", ctypes.c_void_p), ("turn", ctypes.POINTER(MrTurn)),
                ("master_turn", ctypes.POINTER(MrTurn))] + \
        [(n, ctypes.c_int) for n in ("slider", "master_slider", "has_lower", "has_upper")] + \
        [(n, ctypes.c_double) for n in ("mult", "offset", "lower", "upper", "child_inertia")]


class _Soft(ctypes.Structure):
    _fields_ = [("joint", ctypes.c_void_p), ("turn", ctypes.POINTER(MrTurn)), ("lower", ctypes.c_double),
                ("upper", ctypes.c_double)]


class _Batch(ctypes.Structure):
    _fields_ = [("acts", ctypes.c_void_p), ("nacts", ctypes.c_int), ("ndamp", ctypes.c_int),
                ("damp_joints", ctypes.c_void_p), ("damp_kinds", ctypes.c_void_p),
                ("damp_coef", ctypes.c_void_p), ("bodies", ctypes.c_void_p), ("nbodies", ctypes.c_int),
                ("nturns", ctypes.c_int), ("turns", ctypes.c_void_p),
                ("guard_max_contacts", ctypes.c_int), ("max_contacts", ctypes.c_int),
                ("snapshot_interval", ctypes.c_int)] + \
        [(n, ctypes.c_double)
         for n in ("vmax2", "wmax2", "dt", "gx", "gy", "gz", "layer", "time", "last_start")] + \
        [("iterations", ctypes.c_longlong), ("before_due", ctypes.c_double), ("after_due", ctypes.c_double),
         ("publish", ctypes.c_void_p), ("clock_handle", ctypes.c_void_p), ("clock_period", ctypes.c_double),
         ("last_clock", ctypes.c_double), ("ncontacts", ctypes.c_int),
         ("guard", ctypes.c_int), ("world_step", ctypes.c_int), ("first_bad", ctypes.c_int),
         ("after", ctypes.c_int), ("stop_due", ctypes.c_double), ("clock_sent", ctypes.c_int),
         ("nmimic", ctypes.c_int), ("mimics", ctypes.POINTER(_Mimic)), ("nsoft", ctypes.c_int),
         ("softs", ctypes.POINTER(_Soft))] + \
        [(n, ctypes.c_int) for n in ("param_vel", "param_fmax", "param_lo_stop", "param_hi_stop")] + \
        [("mimic_gain", ctypes.c_double), ("mimic_force", ctypes.c_double)]


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


class Batcher(object):
    """Runs batches of steps of ``world`` (native backend only)."""

    def __init__(self, world):
        self.world = world
        self._b = _Batch()
        self._ref = ctypes.byref(self._b)
        self._mimic_src = (None, None)    # (mimics, soft-limit joints) of the arrays below
        self._mimics = self._softs = None
        self.last_start = 0.0
        self.after_due = False

    def eligible(self):
        w = self.world
        return (w.native and not w._wrench_links and not w._anti_gravity and not w._frozen
                and not w._effort_joints and self._mimics_and_soft_ok(w))

    @staticmethod
    def _mimics_and_soft_ok(w):
        for j, m in w._mimics:
            if m.ode_joint is None or not (j.is_angular or j.type == "prismatic") or not (
                    m.is_angular or m.type == "prismatic"):
                return False
        for j in w._soft:
            if not j.is_angular:
                return False
        return True

    def run(self, n, before_due, after_due, clock=None, stop_due=INF):
        """Up to ``n`` steps in C; returns the number done (0: the first step is due for Python).
        A step whose after-hooks are due (it ends at t with t + 1e-12 >= ``after_due``) ends the
        batch with ``after_due`` set: the caller then runs :meth:`run_after_hooks`.
        The World's actuators run at every step; ``clock``: an object with ``publish`` (function
        pointer), ``handle``, ``period`` (0: every step, else at most once per ``period`` s of
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
        acts, nacts = be.actuator_arrays()
        turns, nturns = be.turn_arrays()
        b.acts = ctypes.addressof(acts)
        b.nacts = nacts
        b.turns = ctypes.addressof(turns)
        b.nturns = nturns
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
        if w._mimics or w._soft:
            self._arrange_mimics_and_soft(w._mimics, w._soft)
        b.mimics, b.nmimic = self._mimics, len(w._mimics)
        b.softs, b.nsoft = self._softs, len(w._soft)
        b.param_vel, b.param_fmax = odelib.PARAM_VEL, odelib.PARAM_FMAX
        k = _RUN(be.ctx, self._ref, int(n))
        if k <= 0:
            return 0
        w.time = b.time
        w.iterations = b.iterations
        # what the first step's World._apply_forces did to efforts of the step before that were
        # not commanded again
        for j in w._last_effort_joints:
            j.effort = 0.0
        w._last_effort_joints = []
        if clock is not None:
            clock.last = b.last_clock
            clock.sent = bool(b.clock_sent)
        w._ncontacts = b.ncontacts
        be.batch_done(b.ncontacts, b.first_bad)
        self.last_start = b.last_start
        self.after_due = bool(b.after)
        if b.guard:
            w._guard()
            if w._frozen:
                w._hold_frozen()
        return k

    def _arrange_mimics_and_soft(self, mimics, soft):
        """The mimic and soft-limit joints into the batch (the arrays kept while the World's
        lists are the same; the values refreshed at every batch)."""
        b = self._b
        if self._mimic_src[0] is not mimics or self._mimic_src[1] is not soft:
            self._mimic_src = (mimics, soft)
            self._mimics = (_Mimic * max(1, len(mimics)))()
            self._softs = (_Soft * max(1, len(soft)))()

        def turn(j):
            rec = j.turn_record
            return ctypes.pointer(rec) if isinstance(rec, MrTurn) else ctypes.POINTER(MrTurn)()
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
        b.param_lo_stop, b.param_hi_stop = odelib.PARAM_LO_STOP, odelib.PARAM_HI_STOP
        b.mimic_gain, b.mimic_force = MIMIC_GAIN, MIMIC_COUPLING_FORCE

    def run_after_hooks(self):
        """The World's after-step hooks for the last step of the batch (when ``after_due``: the
        batch made that step because only its after-hooks needed Python)."""
        w = self.world
        t, dt = w.time, w._dt
        for h in w._after:
            h(t, dt)
