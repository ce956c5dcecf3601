"""FrankaHWSim on the physics core with the Panda-style test arm (no ROS): gravity compensation,
the idle hold, the motion generators' PIDs per interface, refusals naming what is missing."""
import os

import pytest
import xacro
import yaml

from franka_sim.hw_sim import FrankaHWSim
from modrob_sim.errors import ControllerError
from modrob_sim.physics import World
from modrob_sim.physics.actuators import PidGains
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.transmissions import CPP_NAMES, POSITION, parse_transmissions

TEST = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
START = {"panda_joint2": 0.4, "panda_joint4": -2.4, "panda_joint6": -0.34}


def motion_generators():
    with open(os.path.join(TEST, "config", "mini_panda_sim.yaml")) as f:
        text = f.read().replace("$(arg arm_id)", "panda")
    values = yaml.safe_load(text)["motion_generators"]
    return Params(values, "/motion_generators")


@pytest.fixture
def arm():
    doc = xacro.process_file(os.path.join(TEST, "fixtures", "mini_panda.urdf.xacro"))
    urdf = doc.toxml()
    world = World(time_step=0.001)
    model = world.add_urdf("panda", urdf, joint_positions=START)
    hw = FrankaHWSim(model, parse_transmissions(urdf), "panda", motion_generators(), world=world)
    return world, model, hw


def run(world, hw, steps):
    for _ in range(steps):
        hw.read()
        hw.write(world.time_step)
        world.step()
    hw.read()


class Claim(object):
    def __init__(self, iface, joints):
        self.claimed_resources = [(CPP_NAMES[iface], joints)]


def test_arm_links_lose_gravity_and_the_idle_arm_holds(arm):
    world, model, hw = arm
    assert "panda_link1" in hw.gravity_free_links and "panda_leftfinger" in hw.gravity_free_links
    assert "panda_link0" not in hw.gravity_free_links and model.links["panda_link0"].gravity_enabled
    fired = []
    hw.on_initialized = lambda: fired.append(True)
    run(world, hw, 1000)
    assert fired == [True]
    assert all(hw.joints[j].owner is hw for j in hw.arm)     # held by the World's actuators
    for name, q in START.items():
        assert hw.joints[name].position == pytest.approx(q, abs=1e-3)


def test_position_interface_runs_the_position_generator(arm):
    world, model, hw = arm
    run(world, hw, 10)
    joints = ["panda_joint%d" % i for i in range(1, 8)]
    hw.do_switch([Claim(POSITION, joints)], [])
    assert hw.joints["panda_joint1"].pid is hw.position_pid["panda_joint1"]
    assert hw.joints["panda_joint1"].owner is None       # the idle hold let go
    hw.joints["panda_joint1"].command = 0.5
    run(world, hw, 2000)
    assert hw.joints["panda_joint1"].position == pytest.approx(0.5, abs=0.01)
    hw.do_switch([], [Claim(POSITION, joints)])     # stopped: holds where it is
    run(world, hw, 1000)
    assert hw.joints["panda_joint1"].position == pytest.approx(0.5, abs=0.01)


def test_missing_arm_joints_and_gains_are_named(arm):
    world, model, hw = arm
    urdf = model.source_xml
    with pytest.raises(ControllerError, match="arm_id 'fr3'.*fr3_joint1"):
        FrankaHWSim(model, parse_transmissions(urdf), "fr3")
    bare = FrankaHWSim(model, parse_transmissions(urdf), "panda", Params({}, "/motion_generators"))
    with pytest.raises(ControllerError, match="motion_generators/position/gains/panda_joint1"):
        bare.do_switch([Claim(POSITION, ["panda_joint1"])], [])


def test_the_idle_hold_needs_no_update_and_takes_new_generator_gains(arm):
    """dynamic_reconfigure's first callback at motion_generators/position/gains/<joint> swaps in
    gains equal to the old ones: after one update the idle arm needs no update in Python again
    (it needed one at every step: the Panda at 1000 per simulated second); changed gains reach the
    hold's actuator."""
    world, model, hw = arm
    run(world, hw, 10)
    assert not hw.needs_every_update
    for j in hw.arm:
        g = hw.position_pid[j].gains
        hw.position_pid[j].set_gains(PidGains(g.p, g.i, g.d, g.i_max, g.i_min, g.antiwindup))
    run(world, hw, 1)
    assert not hw.needs_every_update
    old = hw.position_pid["panda_joint2"].gains
    new = PidGains(2.0 * old.p, old.i, 3.0 * old.d, old.i_max, old.i_min, old.antiwindup)
    hw.position_pid["panda_joint2"].set_gains(new)
    assert hw.needs_every_update
    run(world, hw, 1)
    assert hw.joints["panda_joint2"].actuator.gains.as_dict() == new.as_dict()
    assert hw.joints["panda_joint2"].owner is hw and not hw.needs_every_update
