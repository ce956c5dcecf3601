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

Commands come from the ROS side (actions) through :meth:`command`, which returns a ``Request`` that
the action thread waits on; the update (simulation loop) advances the state and completes it.

Parameters (in the controller's namespace): ``arm_id`` (required), ``finger1/gains`` and
``finger2/gains`` (p, i, d; required), ``publish_rate`` (30), ``move/width_tolerance`` (0.001),
``gripper_action/width_tolerance`` (0.005), ``gripper_action/speed`` (0.1),
``grasp/resting_threshold`` (0.003), ``grasp/consecutive_samples`` (10).
"""
import math
import threading

from modrob_sim.ros_control.controllers.base import Controller
from modrob_sim.ros_control.pid import Pid, PidGains
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
        self.pids = [Pid(PidGains.from_params(params.child(f, required=True).child("gains", required=True)))
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

    # ---- commands (any thread) ------------------------------------------------------------------
    def width(self):
        return self.fingers[0].position + self.fingers[1].position

    def command(self, state, width, speed, force=0.0, inner=None, outer=None):
        """Start a motion (MOVING or GRASPING); the request in progress, if any, ends interrupted.
        Returns the Request to wait on."""
        inner = self.tolerance_move if inner is None else inner
        outer = self.tolerance_move if outer is None else outer
        req = Request(state, width, speed, force, inner, outer)
        with self._lock:
            self._interrupt("Command interrupted, because a new %s command came"
                            % ("grasp" if state == GRASPING else "move"))
            if state == GRASPING:
                current = self.width()
                req.target = 0.0 if width < current else MAX_WIDTH
                req.force = math.copysign(force, width - current)
            else:
                req.target = width
            self.request, self.mode, self._still = req, state, 0
        return req

    def stop(self):
        with self._lock:
            self._interrupt("Command interrupted, because stop action was called")
            self.mode = IDLE

    def _interrupt(self, why):
        if self.request is not None and not self.request.done.is_set():
            self.request.finish(self.mode, self.width(), interrupted=why)
        self.request = None

    # ---- the loop ------------------------------------------------------------------------------
    def starting(self, t):
        for pid in self.pids:
            pid.reset()
        self._last_publish = t - 1.0 / self.publish_rate

    def stopping(self, t):
        self.stop()

    def update(self, t, dt):
        f1, f2 = self.fingers
        if self._last_publish is None or t >= self._last_publish + 1.0 / self.publish_rate - 1e-9:
            self._last_publish = t
            self.pending = (t, list(self.joint_names), [f1.position, f2.position],
                            [f1.velocity, f2.velocity], [f1.effort, f2.effort])
        with self._lock:
            mode, req = self.mode, self.request
            width = f1.position + f2.position
            if mode == IDLE or req is None:
                self._drive(f1.position, f2.position, 0.0, 0.0, dt, mode=IDLE)
                return
            if mode == HOLDING:
                self._drive(f1.position, f2.position, 0.0, req.force / 2.0, dt, mode=HOLDING)
                return
            dw = req.speed * math.copysign(1.0, req.target - width)
            self._drive(f1.position + 0.5 * dw * dt, f2.position + 0.5 * dw * dt, 0.5 * dw, 0.0, dt, mode)
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

    def _drive(self, q1_d, q2_d, dq_d, force, dt, mode):
        f1, f2 = self.fingers
        if mode in (IDLE, HOLDING):       # each finger follows the other one
            q1_d, q2_d = f2.position, f1.position
        for finger, pid, q_d in ((f1, self.pids[0], q1_d), (f2, self.pids[1], q2_d)):
            effort = pid.compute(q_d - finger.position, dt, error_dot=dq_d - finger.velocity) + force
            finger.command = effort

    def release(self):
        """A failed grasp: back to IDLE (franka_gazebo does so after answering)."""
        with self._lock:
            if self.mode == HOLDING:
                self.mode = IDLE
            self.request = None
