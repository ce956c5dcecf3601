"""katana_arm_gazebo's arm gains (config/katana_arm_controller.yaml) on the Katana's URDF, loaded
as the simulator loads them: no gain is named as one that cannot run at the 1 ms step. Each joint
moves the whole arm beyond it (the pan joint 0.25 kg m^2, where its own link alone would be about
0.001 and d = 4 would chatter)."""
import os
import subprocess

import yaml

from modrob_sim import physics
from modrob_sim.ros_control import gain_check
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import ControllerManager
from modrob_sim.ros_control.transmissions import parse_transmissions

PKG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def test_the_published_arm_gains_run_at_the_step():
    xacro = os.path.join(PKG, "urdf", "katana_450_6m90a.urdf.xacro")
    xml = subprocess.check_output(["xacro", xacro, "fixed:=true"], text=True)
    world = physics.World(time_step=0.001)
    model = world.add_urdf("katana", xml)
    with open(os.path.join(PKG, "config", "katana_arm_controller.yaml")) as f:
        params = yaml.safe_load(f)["katana_arm_controller"]
    mgr = ControllerManager(RobotHWSim(model.joints, parse_transmissions(model.source_xml), None), "/")
    mgr.time_step = world.time_step
    logs = []
    mgr.log = lambda level, message: logs.append((level, message))
    controller = mgr.load("katana_arm_controller", params)
    assert controller is not None and [m for level, m in logs if level == "warn"] == []
    pan = gain_check.effective_inertia(model.joints["katana_motor1_pan_joint"])
    assert pan > 0.1 and params["gains"]["katana_motor1_pan_joint"]["d"] * world.time_step / pan < 0.1
