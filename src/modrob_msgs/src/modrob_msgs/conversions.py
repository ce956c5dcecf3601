"""Conversions between modrob_msgs and standard ROS messages (no rospy needed)."""


def joint_state_to_config(joint_state, config_cls):
    """Copy a sensor_msgs/JointState's header, names and positions into a RobotConfigMeasured.

    ``config_cls`` is ``modrob_msgs.msg.RobotConfigMeasured`` (passed in so this module imports
    without the generated code).
    """
    if len(joint_state.name) != len(joint_state.position):
        raise ValueError("JointState has %d names but %d positions"
                         % (len(joint_state.name), len(joint_state.position)))
    msg = config_cls()
    msg.header = joint_state.header
    msg.joint_names = list(joint_state.name)
    msg.joint_angles = list(joint_state.position)
    return msg


def config_to_joint_state(config, joint_state_cls):
    """The inverse of :func:`joint_state_to_config` (positions only)."""
    if len(config.joint_names) != len(config.joint_angles):
        raise ValueError("RobotConfigMeasured has %d joint names but %d angles"
                         % (len(config.joint_names), len(config.joint_angles)))
    msg = joint_state_cls()
    msg.header = config.header
    msg.name = list(config.joint_names)
    msg.position = list(config.joint_angles)
    return msg
