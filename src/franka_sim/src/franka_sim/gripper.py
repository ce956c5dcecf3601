"""``franka_gazebo/FrankaGripperSim``: the Franka Hand as franka_gazebo simulates it (pure).

A controller on the two finger joints' effort interface. Widths are the sum of both finger
positions (0 .. 0.08 m). States:

- IDLE: each finger follows the other one (a soft mimic) at zero velocity;
- MOVING: both fingers move towards ``width`` at ``speed``; done (back to IDLE) when the width is
  within the tolerance, or when the fingers stop (an object in the way: IDLE, move failed);
- GRASPING: the fingers close (or open) at ``speed`` until they stop on an object (the finger
  speed stays below ``grasp/resting_threshold`` for ``grasp/consecutive_samples`` updates): then
  HOLDING with the grasp force, and the grasp succeeded when the width is within
  ``width - epsilon.inner .. width + epsilon.outer``;
- HOLDING: each finger follows the other one and pushes with half the force.

Each finger's PID is its joint's actuator (a FOLLOW_PID of the World: docs/controllers.md), which
the controller holds from ``starting`` to ``stopping``, so the PID's state goes on from one state
to the next. In IDLE and HOLDING the actuators follow each other (the derivative against velocity
0, HOLDING's half force as their bias) at every step, natively, and the update is due only for
the 30 Hz joint states and a new command; in MOVING and GRASPING an update at every step gives
each actuator its set-point (where the finger is plus half a step of the width's motion) and checks
the width and the fingers' rest.

Commands come from the ROS side (actions) through :meth:`command`, which returns a ``Request`` that
the action thread waits on, and calls ``on_change`` (the ROS side: its context's wake) so that the
next update runs at once; the update (simulation loop) advances the state and completes it.

Parameters (in the controller's namespace): ``arm_id`` (required), ``finger1/gains`` and
``finger2/gains`` (p, i, d; required), ``publish_rate`` (30), ``move/width_tolerance`` (0.001),
``gripper_action/width_tolerance`` (0.005), ``gripper_action/speed`` (0.1),
``grasp/resting_threshold`` (0.003), ``grasp/consecutive_samples`` (10).
"""
import math
import threading

from modrob_sim.errors import InputError
from modrob_sim.physics.actuators import FOLLOW_PID
from modrob_sim.ros_control.controllers.base import Controller
from modrob_sim.ros_control.pid import PidGains
from modrob_sim.ros_control.transmissions import EFFORT

MAX_WIDTH = 0.08
HOMING_SPEED = 0.02
MIN_GRASP_FORCE = 1e-4
IDLE, MOVING, GRASPING, HOLDING = "IDLE", "MOVING", "GRASPING", "HOLDING"


class Request(object):
    """One commanded motion: the action thread waits for ``done``; ``state`` is the state it
    ended in, ``width`` the width then; ``interrupted`` names what cut it short."""

    def __init__(self, state, width, speed, force, inner, outer):
        self.state, self.width, self.speed, self.force = state, width, speed, force
        self.inner, self.outer = inner, outer
        self.done = threading.Event()
        self.final_state = None
        self.final_width = None
        self.interrupted = None

    def finish(self, state, width, interrupted=None):
        self.final_state, self.final_width, self.interrupted = state, width, interrupted
        self.done.set()

    def within(self, target=None):
        """True when the final width is inside the request's tolerance around ``target``."""
        target = self.width if target is None else target
        return self.final_width is not None and \
            target - self.inner < self.final_width < target + self.outer


class FrankaGripperSim(Controller):
    TYPE = "franka_gazebo/FrankaGripperSim"
    INTERFACE = EFFORT

    def __init__(self, name, hw, params):
        super(FrankaGripperSim, self).__init__(name, hw, params)
        self.arm_id = params.get("arm_id", kind=str)
        self.joint_names = [self.arm_id + "_finger_joint1", self.arm_id + "_finger_joint2"]
        self.fingers = [hw.joint(n, EFFORT, controller=name) for n in self.joint_names]
        self.gains = [PidGains.from_params(params.child(f, required=True).child("gains", required=True))
                      for f in ("finger1", "finger2")]
        self.publish_rate = params.get("publish_rate", 30.0, kind=float)
        self.tolerance_move = params.child("move").get("width_tolerance", 0.001, kind=float)
        action = params.child("gripper_action")
        self.tolerance_gripper_action = action.get("width_tolerance", 0.005, kind=float)
        self.default_speed = action.get("speed", 0.1, kind=float)
        grasp = params.child("grasp")
        self.resting_threshold = grasp.get("resting_threshold", 0.003, kind=float)
        self.resting_samples = int(grasp.get("consecutive_samples", 10))
        self._lock = threading.Lock()
        self.mode = IDLE
        self.request = None
        self._still = 0
        self._last_publish = None
        self.acts = None        # the fingers' actuators (FOLLOW_PID), from starting to stopping
        self._held = None       # what the actuators do natively: (IDLE or HOLDING, bias), else None
        #: called after a command, a stop or a release (the ROS side: its context's wake)
        self.on_change = None

    # ---- commands (any thread) ------------------------------------------------------------------
    def width(self):
        return self.fingers[0].position + self.fingers[1].position

    def command(self, state, width, speed, force=0.0, inner=None, outer=None):
        """Start a motion (MOVING or GRASPING); the request in progress, if any, ends interrupted.
        Returns the Request to wait on. A grasp's direction (and its force's sign) is taken from
        the width at the next update. A value that is not a finite number raises InputError (naming
        it) and changes nothing."""
        inner = self.tolerance_move if inner is None else inner
        outer = self.tolerance_move if outer is None else outer
        for what, value in (("width", width), ("speed", speed), ("force", force), ("epsilon.inner", inner),
                            ("epsilon.outer", outer)):
            if not math.isfinite(value):
                raise InputError("%s: the command's %s %r is not a finite number; nothing was changed: "
                                 "send finite values (width m, speed m/s, force N, epsilon m)"
                                 % (self.name, what, value))
        req = Request(state, width, speed, force, inner, outer)
        req.target = width if state == MOVING else None
        with self._lock:
            self._interrupt("Command interrupted, because a new %s command came"
                            % ("grasp" if state == GRASPING else "move"))
            self.request, self.mode, self._still = req, state, 0
        self._changed()
        return req

    def stop(self):
        with self._lock:
            self._interrupt("Command interrupted, because stop action was called")
            self.mode = IDLE
        self._changed()

    def _interrupt(self, why):
        if self.request is not None and not self.request.done.is_set():
            self.request.finish(self.mode, self.width(), interrupted=why)
        self.request = None

    def _changed(self):
        cb = self.on_change
        if cb is not None:
            cb()

    # ---- the loop ------------------------------------------------------------------------------
    def starting(self, t):
        self.acts = [finger.actuate(FOLLOW_PID, gains, owner=self)
                     for finger, gains in zip(self.fingers, self.gains)]
        self._held = None
        self._last_publish = t - 1.0 / self.publish_rate

    def stopping(self, t):
        self.stop()
        for finger, a in zip(self.fingers, self.acts or ()):
            if finger.owner is self:
                # the hardware keeps applying the last effort, as ros_control's does
                finger.command = a.last.output
                finger.release()
        self.acts = None
        self._held = None

    def _publish_due(self):
        return self._last_publish + 1.0 / self.publish_rate - 1e-9

    def _native_rule(self):
        """What the actuators do on their own in this state: (IDLE or HOLDING, the bias), or None
        (MOVING, GRASPING: an update at every step)."""
        mode, req = self.mode, self.request
        if mode == IDLE or req is None:
            return (IDLE, 0.0)
        if mode == HOLDING:
            return (HOLDING, req.force / 2.0)
        return None

    def update_due(self, t, iteration, dt):
        """In IDLE and HOLDING the joint states' next publication (and at once after a command);
        in MOVING and GRASPING every update."""
        with self._lock:
            rule = self._native_rule()
        if rule is None or rule != self._held or self._last_publish is None:
            return t
        return self._publish_due()

    def update(self, t, dt):
        f1, f2 = self.fingers
        if self._last_publish is None or t >= self._publish_due():
            self._last_publish = t
            self.pending = (t, list(self.joint_names), [f1.position, f2.position],
                            [f1.velocity, f2.velocity], [f1.effort, f2.effort])
        with self._lock:
            rule = self._native_rule()
            if rule is not None:
                self._follow_each_other(rule)
                return
            mode, req = self.mode, self.request
            width = f1.position + f2.position
            if req.target is None:           # a new grasp: towards 0 or fully open, its force's sign too
                req.target = 0.0 if req.width < width else MAX_WIDTH
                req.force = math.copysign(req.force, req.width - width)
            dw = req.speed * math.copysign(1.0, req.target - width)
            self._held = None
            for a, finger in zip(self.acts, self.fingers):
                a.follow(finger.sim, 1.0, 0.5 * dw * dt, velocity=0.5 * dw)
            if mode == MOVING and req.target - req.inner < width < req.target + req.outer:
                self.mode = IDLE
                req.finish(IDLE, width)
                return
            speed = f1.velocity + f2.velocity
            self._still = self._still + 1 if abs(speed) <= self.resting_threshold else 0
            if self._still >= self.resting_samples:
                self._still = 0
                self.mode = HOLDING if mode == GRASPING else IDLE
                req.finish(self.mode, width)
                if mode != GRASPING:
                    self.request = None

    def _follow_each_other(self, rule):
        """IDLE and HOLDING: each finger's set-point is the other finger's position, at velocity 0,
        plus the bias (HOLDING: half the grasp force); the actuators run it at every step."""
        if rule == self._held:
            return
        a1, a2 = self.acts
        f1, f2 = self.fingers
        bias = rule[1]
        a1.follow(f2.sim, 1.0, 0.0, velocity=0.0, bias=bias)
        a2.follow(f1.sim, 1.0, 0.0, velocity=0.0, bias=bias)
        self._held = rule

    def release(self):
        """A failed grasp: back to IDLE (franka_gazebo does so after answering)."""
        with self._lock:
            if self.mode == HOLDING:
                self.mode = IDLE
            self.request = None
        self._changed()
