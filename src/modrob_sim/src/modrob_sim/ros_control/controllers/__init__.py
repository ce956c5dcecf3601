"""ros_controllers' controllers, pure (no rospy). ``CONTROLLER_TYPES`` maps ros_control type
names to classes."""
from modrob_sim.ros_control.controllers.ackermann_steering import AckermannSteeringController
from modrob_sim.ros_control.controllers.diff_drive import DiffDriveController
from modrob_sim.ros_control.controllers.forward_command import (
    EffortJointEffortController, PositionJointPositionController, VelocityJointVelocityController)
from modrob_sim.ros_control.controllers.effort_joint_position import (EffortJointPositionController,
                                                                      VelocityJointPositionController)
from modrob_sim.ros_control.controllers.effort_joint_velocity import EffortJointVelocityController
from modrob_sim.ros_control.controllers.gripper_action import (EffortGripperActionController,
                                                               PositionGripperActionController)
from modrob_sim.ros_control.controllers.joint_group import (
    EffortJointGroupEffortController, EffortJointGroupPositionController,
    PositionJointGroupPositionController, VelocityJointGroupVelocityController)
from modrob_sim.ros_control.controllers.joint_state import JointStateController
from modrob_sim.ros_control.controllers.joint_trajectory import (
    EffortJointTrajectoryController, PositionJointTrajectoryController, VelocityJointTrajectoryController)

CONTROLLER_TYPES = {cls.TYPE: cls for cls in (
    JointStateController,
    EffortJointPositionController,
    EffortJointVelocityController,
    EffortJointEffortController,
    PositionJointPositionController,
    VelocityJointVelocityController,
    VelocityJointPositionController,
    PositionJointGroupPositionController,
    VelocityJointGroupVelocityController,
    EffortJointGroupEffortController,
    EffortJointGroupPositionController,
    PositionJointTrajectoryController,
    VelocityJointTrajectoryController,
    EffortJointTrajectoryController,
    PositionGripperActionController,
    EffortGripperActionController,
    DiffDriveController,
    AckermannSteeringController,
)}
