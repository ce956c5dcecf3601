"""The Bulbs and Slides robot (the seed's 6-joint order with the gripper, its generated URDF and
controller YAML) under the scenario's controllers, stepped as the /gazebo node steps it: the
joint_state_controller at 50 Hz, the JointPositionControllers holding, then the scenario's
JointTrajectoryController with a goal of points every 10 ms (as ros_robot.execute sends them) and
the gripper closed by set-points streamed at 100 Hz (as motion_publisher streams them).

Every step is made in C: an update that is due runs in Python and that step's physics in C
(World.hooked_steps), no step's physics runs in Python. The updates in Python are the due ones
only (joint_states samples, segment ends, state samples, commands), a few in a hundred steps; and
the steps are those of updating at every step, bit for bit. If a controller of this set-up lost
its due times (an update at every step) or the World made its due steps in Python again, the
scenario would lose the fast path: these checks fail."""
import collections

import pytest
import yaml

from modrob_build.build import RobotSpec, build_robot_set
from modrob_sim.gazebo_ros.testing import ControlRig
from modrob_sim.physics import native as native_mod
from modrob_sim.ros_control.controllers.joint_trajectory import TrajectoryPoint
from modrob_sim.ros_control.manager import STRICT

SEED_6DOF = [59, 3, 55, 63, 64, 4, 66, 4, 67, 5, 56, 5]
FINGER = "gripper_finger1_position_controller"
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


@pytest.fixture(scope="module")
def robot_files():
    result = build_robot_set([RobotSpec(SEED_6DOF)], gripper=True)
    return result.files["modrob0.urdf"], yaml.safe_load(result.files["modrob0_controllers.yaml"])["modrob0"]


class ScenarioRig(ControlRig):
    """modrob0 with its controllers as the scenario loads them; nobody subscribed to the
    controllers' state topics (the scenario does not listen to them)."""

    def __init__(self, files, fast):
        urdf, cfg = files
        super(ScenarioRig, self).__init__(urdf, name="modrob0")
        self.joint_state_controller(cfg["joint_state_controller"]["publish_rate"])
        names = [n for n in cfg if n != "joint_state_controller"]
        for n in names:
            c = self.mgr.load(n, cfg[n])
            c.state_wanted = lambda: False
            self.adapter(n)
        self.arm = [n for n in names if n != FINGER]
        self.arm_joints = [cfg[n]["joint"] for n in self.arm]
        # the scenario's trajectory controller: the position controllers' gains, goal_time and
        # stopped_velocity_tolerance, states at 25 Hz (modrob_motion's ros_robot)
        self.jtc = self.mgr.load("arm_trajectory_controller", {
            "type": "effort_controllers/JointTrajectoryController", "joints": self.arm_joints,
            "gains": {cfg[n]["joint"]: cfg[n]["pid"] for n in self.arm},
            "constraints": {"goal_time": 0.5, "stopped_velocity_tolerance": 0.05},
            "state_publish_rate": 25.0})
        self.inbox = collections.deque()
        self.adapter("arm_trajectory_controller", waiting=lambda: bool(self.inbox),
                     before_update=self._jtc_before, after_update=self._jtc_after)
        assert self.mgr.switch(["jsc"] + names, [], STRICT)[0]
        self.start(fast)

    def _jtc_before(self, t):
        while self.inbox:
            self.log.append(("submit", t, self.jtc.submit(*self.inbox.popleft(), start_time=0.0, now=t,
                                                          goal_id="g")))

    def _jtc_after(self, t):
        c = self.jtc
        self.log.extend(("event", t) + e for e in c.events)
        del c.events[:]
        for name in ("pending", "pending_feedback"):
            data = getattr(c, name, None)
            if data is not None:
                self.log.append((name, t, data))
                setattr(c, name, None)

    def to_trajectory_controller(self):
        assert self.mgr.switch(["arm_trajectory_controller"], self.arm, STRICT)[0]

    def goal(self, seconds=0.4, period=0.01, amplitude=0.1):
        """Every arm joint by ``amplitude`` rad along a smoothstep, a point every ``period``."""
        q0 = [self.model.joints[j].position for j in self.arm_joints]
        points, n = [], int(round(seconds / period))
        for k in range(1, n + 1):
            s = k / n
            shape, slope = 3 * s * s - 2 * s ** 3, (6 * s - 6 * s * s) / seconds
            points.append(TrajectoryPoint([q + amplitude * shape for q in q0],
                                          [amplitude * slope for _ in q0], time_from_start=k * period))
        self.inbox.append((self.arm_joints, points))
        self.world.wake()

    def finger_setpoint(self, q):
        self.mgr.get(FINGER).set_command(q)


def scenario(rig):
    """1.5 s: the arm holding (0.3 s), the trajectory controller's goal of 0.4 s and settling, the
    gripper closing by set-points at 100 Hz over 0.3 s; steps in passes of 10 as the node's loop.
    Returns the steps of the hold, of the motion with the gripper's stream, and of the rest."""
    spans = []

    def run(steps, each=None):
        i0, n0, h0 = rig.world.iterations, rig.world.native_steps, rig.world.hooked_steps
        while rig.world.iterations < i0 + steps:
            if each is not None:
                each(rig.world.iterations - i0)
            rig.step(10)
        spans.append((rig.world.iterations - i0, rig.world.native_steps - n0, rig.world.hooked_steps - h0))
    run(300)
    rig.to_trajectory_controller()
    rig.goal()
    opened = rig.model.joints["gripper_finger1_joint"].position
    run(600, lambda k: rig.finger_setpoint(opened - 0.01 * min(1.0, k / 300.0)) if k % 10 == 0 else None)
    run(600)
    return spans


@needs_c
def test_the_scenario_steps_natively_with_only_its_due_updates_in_python(robot_files):
    ref, fast = ScenarioRig(robot_files, False), ScenarioRig(robot_files, True)
    scenario(ref)
    spans = scenario(fast)
    # the same steps as updating at every step
    assert ref.log == fast.log
    assert [e for e in fast.log if e[0] == "event"][-1][3] == "succeeded", fast.log[-3:]
    assert ref.world.state_digest() == fast.world.state_digest()
    assert sum(1 for e in fast.log if e[0] == "joint_states") == 75
    w = fast.world
    # no step's physics in Python
    assert w.native_steps + w.hooked_steps == w.iterations == 1500, (w.native_steps, w.hooked_steps)
    (hold, hold_nat, hold_py), (move, _, move_py), (rest, _, rest_py) = spans
    # Python updates, all on the 10 ms grid of the points and set-points: holding, the first update
    # and the joint_states samples (50 Hz); moving, the segment ends and the finger's set-points
    # (100 Hz, with the samples and the 25 Hz states among them); then the samples and states
    assert hold_py <= 1 + hold // 20, spans
    assert move_py <= 2 + move // 10, spans
    assert rest_py <= 2 + rest // 20 + rest // 40, spans
