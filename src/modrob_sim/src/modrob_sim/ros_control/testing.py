"""A tiny pure-Python plant with the physics core's Joint interface, for tests and quick
experiments without ODE: one rigid body on one joint, I * qdd = u - b * qd (+ gravity torque
m g l sin q if given), semi-implicit Euler. Efforts are clamped to +-effort_limit like the core."""
import math


class IntegratorJoint(object):
    def __init__(self, name="joint", type_="revolute", inertia=0.1, damping=0.0, lower=None, upper=None,
                 effort_limit=None, velocity_limit=None, position=0.0, gravity_torque=0.0):
        self.name, self.type = name, type_
        self.inertia, self.damping = float(inertia), float(damping)
        self.lower, self.upper = lower, upper
        self.effort_limit, self.velocity_limit = effort_limit, velocity_limit
        self.position, self.velocity, self.effort = float(position), 0.0, 0.0
        self.gravity_torque = gravity_torque
        self._effort = 0.0
        self._kinematic = None
        self._motor = None
        self._own_motor = None

    def set_effort(self, f):
        if not math.isfinite(f):
            raise ValueError("effort %r for joint %s is not finite" % (f, self.name))
        if self.effort_limit is not None:
            f = max(-self.effort_limit, min(self.effort_limit, f))
        self._effort = f

    def limit_effort(self, f):
        if self.effort_limit is not None:
            f = max(-self.effort_limit, min(self.effort_limit, f))
        return f

    def add_raw_effort(self, f):
        """An actuator's effort for this step (already clamped)."""
        self._effort += f

    def drive_motor(self, v, max_force):
        """An actuator's motor velocity for this step (OUT_VELOCITY, MOTOR)."""
        self._motor = None if max_force <= 0 else (float(v), float(max_force))

    def release_motor(self):
        """The actuator lets the motor go: the joint's own (set_velocity_target) again."""
        self._motor = self._own_motor

    def set_position(self, q):
        self._kinematic = float(q)

    def set_velocity_target(self, v, max_force):
        self._motor = self._own_motor = None if max_force <= 0 else (float(v), float(max_force))

    def step(self, dt):
        if self._kinematic is not None:
            self.position, self.velocity, self.effort = self._kinematic, 0.0, 0.0
            self._kinematic = None
            return
        u = self._effort - self.damping * self.velocity
        if self.gravity_torque:
            u -= self.gravity_torque * math.sin(self.position)
        if self._motor is not None:
            v, fmax = self._motor
            need = self.inertia * (v - self.velocity) / dt - u   # force making the velocity exact
            u += max(-fmax, min(fmax, need))
        self.effort = self._effort
        self.velocity += u / self.inertia * dt
        self.position += self.velocity * dt
        if self.lower is not None and self.type != "continuous" and self.position < self.lower:
            self.position, self.velocity = self.lower, 0.0
        if self.upper is not None and self.type != "continuous" and self.position > self.upper:
            self.position, self.velocity = self.upper, 0.0
        self._effort = 0.0


class IntegratorModel(object):
    """A set of independent IntegratorJoints stepped together; ``run(manager, seconds)``."""

    def __init__(self, joints):
        self.joints = {j.name: j for j in joints}
        self.time = 0.0

    def step(self, dt):
        for j in self.joints.values():
            j.step(dt)
        self.time += dt

    def run(self, manager, seconds, dt=0.001, record=None):
        n = int(round(seconds / dt))
        for _ in range(n):
            manager.update(self.time, dt)
            self.step(dt)
            if record is not None:
                record(self.time)


def simple_transmissions(interfaces):
    """{joint: 'EffortJointInterface'|...} -> TransmissionInfo list (SimpleTransmission, reduction 1)."""
    from modrob_sim.ros_control.transmissions import TransmissionActuator, TransmissionInfo, TransmissionJoint
    return [TransmissionInfo(j + "_trans", "transmission_interface/SimpleTransmission",
                             [TransmissionJoint(j, ["hardware_interface/" + iface])],
                             [TransmissionActuator(j + "_motor", 1.0, [])])
            for j, iface in interfaces.items()]
