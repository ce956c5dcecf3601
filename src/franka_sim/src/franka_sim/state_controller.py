"""``franka_control/FrankaStateController``: the arm's state at ``publish_rate`` (pure).

Claims ``franka_hw/FrankaStateInterface`` (the resource ``<arm_id>_robot``), as the real
controller does, and reads the 7 arm joints (``joint_names``, required) from the hardware. Each
publish leaves in ``pending`` what the ROS side sends: the joint states (position, velocity,
effort) for ``joint_states``, the desired ones for ``joint_states_desired`` and the fields of
franka_msgs/FrankaState that the simulation knows (q, dq, tau_J, q_d, dq_d, robot_mode, time).
"""
from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.controllers.base import Controller
from modrob_sim.ros_control.transmissions import POSITION, VELOCITY

CPP_STATE_INTERFACE = "franka_hw::FrankaStateInterface"
ROBOT_MODE_IDLE, ROBOT_MODE_MOVE = 1, 2


class FrankaStateController(Controller):
    TYPE = "franka_control/FrankaStateController"

    def __init__(self, name, hw, params):
        super(FrankaStateController, self).__init__(name, hw, params)
        self.arm_id = params.get("arm_id", kind=str)
        self.joint_names = params.get("joint_names", kind=list)
        if len(self.joint_names) != 7:
            raise ControllerError("Parameter %s must name the 7 arm joints, got %d"
                                  % (params.path("joint_names"), len(self.joint_names)))
        self.joints = [hw.joint(n, controller=name) for n in self.joint_names]
        resources = getattr(hw, "resource_names", lambda iface: [])("franka_hw/FrankaStateInterface")
        if not resources:
            raise ControllerError("controller '%s' (%s) needs the robot hardware franka_gazebo/FrankaHWSim "
                                  "with a franka_hw/FrankaStateInterface transmission (<robotSimType> of "
                                  "the gazebo_ros_control plugin)" % (name, self.TYPE))
        self.resource = resources[0]
        self.publish_rate = params.get("publish_rate", 30.0, kind=float)
        if self.publish_rate <= 0.0:
            raise ControllerError("Parameter %s must be > 0" % params.path("publish_rate"))
        self._last_publish = None

    @property
    def claimed_resources(self):
        return [(CPP_STATE_INTERFACE, [self.resource])]

    def starting(self, t):
        self._last_publish = t - 1.0 / self.publish_rate

    def update_due(self, t, iteration, dt):
        """Only its publications need Python (it commands nothing)."""
        return t if self._last_publish is None else self._last_publish + 1.0 / self.publish_rate - 1e-9

    def update(self, t, dt):
        if self._last_publish is not None and t < self._last_publish + 1.0 / self.publish_rate - 1e-9:
            return
        if self._last_publish is None or t - self._last_publish > 2.0 / self.publish_rate:
            self._last_publish = t
        else:
            self._last_publish += 1.0 / self.publish_rate
        q = [j.position for j in self.joints]
        dq = [j.velocity for j in self.joints]
        tau = [j.effort for j in self.joints]
        claimed = getattr(self.hw, "claimed", set())
        held = getattr(self.hw, "stop_position", {})
        q_d, dq_d = [], []
        for j in self.joints:
            if j.name not in claimed:
                q_d.append(held.get(j.name, j.position))
            else:
                q_d.append(j.command if j.interface == POSITION else j.position)
            dq_d.append(j.command if j.name in claimed and j.interface == VELOCITY else 0.0)
        mode = ROBOT_MODE_MOVE if any(n in claimed for n in self.joint_names) else ROBOT_MODE_IDLE
        self.pending = dict(t=t, names=list(self.joint_names), q=q, dq=dq, tau_J=tau, q_d=q_d, dq_d=dq_d,
                            robot_mode=mode)
