"""The ros_control controller configuration of one robot (the YAML the spawner reads).

    modrob<N>:
      joint_state_controller: {type: joint_state_controller/JointStateController, publish_rate: 50}
      joint<M>_position_controller:
        type: effort_controllers/JointPositionController
        joint: joint<M>
        pid: {p: ..., i: ..., d: ..., i_clamp: ..., antiwindup: true}
      gripper_finger1_position_controller: ...       (with the gripper; finger 2 mimics finger 1
                                                       and, as in ros_control, has no controller)
"""
import yaml

from modrob_build import gains as gains_mod
from modrob_build.gripper import GRIPPER_ACTUATED_JOINTS

JOINT_STATE_RATE = 50


def controller_names(robot, gripper=False):
    """Controllers in spawn order: joint_state_controller, joint1.., the gripper's actuated finger."""
    names = ["joint_state_controller"]
    names += ["%s_position_controller" % j.name for j in robot.actuated_joints]
    if gripper:
        names += ["%s_position_controller" % j.replace("_joint", "") for j in GRIPPER_ACTUATED_JOINTS]
    return names


def controller_config(robot, gripper=False, grip_force=3.0, dt=gains_mod.TIME_STEP, tuned=None,
                      sources=None):
    """{robot name: {controller: params}} (plain dict, insertion-ordered).

    tuned: {joint: {p, i, d, i_clamp}} from the tuner's table (modrob_build.tuned_gains); joints
    not in it get the gains computed from the inertias. sources (a dict, filled if given):
    joint -> "tuned" | "computed"."""
    cfg = {"joint_state_controller": {"type": "joint_state_controller/JointStateController",
                                      "publish_rate": JOINT_STATE_RATE}}
    payload = gains_mod.GRIPPER_PAYLOAD if gripper else None
    tuned = tuned or {}
    for load in gains_mod.joint_loads(robot, payload):
        if load.joint in tuned:
            pid = {k: round(float(tuned[load.joint][k]), 4) for k in ("p", "i", "d", "i_clamp")}
            pid["antiwindup"] = True
            source = "tuned"
        else:
            pid = gains_mod.pid_from_load(load, dt=dt).as_dict()
            source = "computed"
        if sources is not None:
            sources[load.joint] = source
        cfg["%s_position_controller" % load.joint] = {
            "type": "effort_controllers/JointPositionController", "joint": load.joint, "pid": pid}
    if gripper:
        for joint in GRIPPER_ACTUATED_JOINTS:
            g = gains_mod.finger_gains(gains_mod.finger_load(joint, grip_force), dt=dt)
            cfg["%s_position_controller" % joint.replace("_joint", "")] = {
                "type": "effort_controllers/JointPositionController", "joint": joint,
                "pid": g.as_dict()}
    return {robot.name: cfg}


def controller_yaml(robot, gripper=False, grip_force=3.0, header=None, tuned=None, sources=None):
    text = yaml.safe_dump(controller_config(robot, gripper, grip_force, tuned=tuned, sources=sources),
                          sort_keys=False,
                          default_flow_style=False)
    if header:
        text = "".join("# %s\n" % line for line in header.splitlines()) + text
    return text
