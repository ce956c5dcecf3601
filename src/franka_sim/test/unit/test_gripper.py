"""FrankaGripperSim's state machine on two simulated prismatic fingers (no ROS): move, grasp on an
object, a grasp outside its epsilon, stop; as franka_gazebo's FrankaGripperSim behaves."""
import threading

import pytest

from franka_sim.gripper import GRASPING, HOLDING, IDLE, MOVING, FrankaGripperSim
from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.transmissions import EFFORT

PARAMS = {"arm_id": "panda", "finger1": {"gains": {"p": 100, "d": 1.0}},
          "finger2": {"gains": {"p": 100, "d": 1.0}}}


class Finger(object):
    """A 20 g finger on a prismatic joint with damping, stopped by an object at ``stop``."""

    def __init__(self, name):
        self.name, self.position, self.velocity, self.effort, self.command = name, 0.02, 0.0, 0.0, 0.0
        self.interface = EFFORT
        self.stop = 0.0

    def step(self, dt):
        self.effort = max(-100.0, min(100.0, self.command))
        self.velocity += (self.effort - 0.3 * self.velocity) / 0.02 * dt
        at_stop = self.position <= self.stop and self.velocity < 0.0
        if at_stop or (self.position >= 0.04 and self.velocity > 0.0):
            self.velocity = 0.0         # a joint stop (a constraint in ODE): no bounce
        self.position = min(max(self.position + self.velocity * dt, self.stop), 0.04)


class Hand(object):
    def __init__(self):
        self.joints = {n: Finger(n) for n in ("panda_finger_joint1", "panda_finger_joint2")}

    def joint(self, name, interface=None, controller=""):
        if name not in self.joints:
            raise ControllerError("no joint %s" % name)
        return self.joints[name]


def run(gripper, hand, seconds, dt=0.001, t0=0.0):
    t = t0
    for _ in range(int(seconds / dt)):
        gripper.update(t, dt)
        for f in hand.joints.values():
            f.step(dt)
        t += dt
    return t


@pytest.fixture
def setup():
    hand = Hand()
    g = FrankaGripperSim("franka_gripper", hand, Params(PARAMS, "/franka_gripper"))
    g.starting(0.0)
    return g, hand


def test_move_reaches_the_width(setup):
    g, hand = setup
    req = g.command(MOVING, 0.06, 0.1)
    run(g, hand, 1.0)
    assert req.done.is_set() and req.final_state == IDLE and req.within()
    assert g.width() == pytest.approx(0.06, abs=0.002)


def test_grasp_holds_an_object_with_the_force(setup):
    g, hand = setup
    g.command(MOVING, 0.08, 0.1)
    run(g, hand, 1.0)
    for f in hand.joints.values():
        f.stop = 0.015                 # a 3 cm object between the fingers
    req = g.command(GRASPING, 0.03, 0.05, force=20.0, inner=0.005, outer=0.005)
    run(g, hand, 2.0)
    assert req.final_state == HOLDING and req.within()
    assert g.mode == HOLDING
    # holding: each finger pushes with half the force (closing is the negative direction)
    assert sum(f.command for f in hand.joints.values()) == pytest.approx(-20.0, abs=1.0)


def test_grasp_that_closes_beyond_epsilon_fails(setup):
    g, hand = setup
    g.command(MOVING, 0.08, 0.1)
    run(g, hand, 1.0)
    req = g.command(GRASPING, 0.05, 0.1, force=10.0, inner=0.002, outer=0.002)   # nothing there
    run(g, hand, 2.0)
    assert req.done.is_set() and not req.within()


def test_a_blocked_move_ends_idle_and_a_new_command_interrupts(setup):
    g, hand = setup
    for f in hand.joints.values():
        f.stop = 0.015
    req = g.command(MOVING, 0.0, 0.1)
    run(g, hand, 2.0)
    assert req.final_state == IDLE and not req.within()
    first = g.command(MOVING, 0.08, 0.01)
    second = g.command(MOVING, 0.05, 0.1)
    assert first.done.is_set() and "interrupted" in first.interrupted
    g.stop()
    assert second.done.is_set() and g.mode == IDLE


def test_missing_gains_are_named():
    params = Params({"arm_id": "panda", "finger1": {"gains": {"p": 1}}}, "/franka_gripper")
    with pytest.raises(ControllerError, match="finger2"):
        FrankaGripperSim("franka_gripper", Hand(), params)


def test_commands_from_another_thread(setup):
    g, hand = setup
    out = {}
    th = threading.Thread(target=lambda: out.setdefault("req", g.command(MOVING, 0.07, 0.1)))
    th.start()
    th.join()
    run(g, hand, 1.0)
    assert out["req"].done.wait(0) and out["req"].within()
