"""joint_state_controller/JointStateController: publishes every joint's position, velocity and
effort as sensor_msgs/JointState on ``<ns>/joint_states`` at ``publish_rate`` (required, as in
ros_controllers) plus optional ``extra_joints`` (name, position, velocity, effort) at fixed values."""
from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.controllers.base import Controller


class JointStateController(Controller):
    TYPE = "joint_state_controller/JointStateController"

    def __init__(self, name, hw, params):
        super(JointStateController, self).__init__(name, hw, params)
        if not params.has("publish_rate"):
            raise ControllerError("Parameter %s is missing: JointStateController needs publish_rate "
                                  "(e.g. 'publish_rate: 50')" % params.path("publish_rate"))
        self.publish_rate = params.get("publish_rate", kind=float)
        if self.publish_rate <= 0.0:
            raise ControllerError("Parameter %s must be > 0, got %g"
                                  % (params.path("publish_rate"), self.publish_rate))
        self.extra = []
        for i, extra in enumerate(params.values.get("extra_joints", []) or []):
            if not isinstance(extra, dict) or "name" not in extra:
                raise ControllerError("Parameter %s[%d] must be {name: ..., position: ..., velocity: ..., "
                                      "effort: ...}" % (params.path("extra_joints"), i))
            self.extra.append((str(extra["name"]), float(extra.get("position", 0.0)),
                               float(extra.get("velocity", 0.0)), float(extra.get("effort", 0.0))))
        self.state_names = list(hw.order)
        self._last_publish = None

    def starting(self, t):
        self._last_publish = t - 1.0 / self.publish_rate

    def next_due(self):
        """The time from which an update publishes (None before the controller has started)."""
        if self._last_publish is None:
            return None
        return self._last_publish + 1.0 / self.publish_rate - 1e-9

    def update_due(self, t, iteration, dt):
        due = self.next_due()
        return t if due is None else due

    def update(self, t, dt):
        if self._last_publish is not None and t < self.next_due():
            return
        # ros_controllers advances by whole periods, so the average rate stays exact
        if self._last_publish is None or t - self._last_publish > 2.0 / self.publish_rate:
            self._last_publish = t
        else:
            self._last_publish += 1.0 / self.publish_rate
        joints = [self.hw.joints[n] for n in self.state_names]
        names = self.state_names + [e[0] for e in self.extra]
        self.pending = (t, names,
                        [j.position for j in joints] + [e[1] for e in self.extra],
                        [j.velocity for j in joints] + [e[2] for e in self.extra],
                        [j.effort for j in joints] + [e[3] for e in self.extra])
