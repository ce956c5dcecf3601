"""Where a joint is exercised. A loop steps one joint with an effort chosen each step while every
other joint of the robot is held where it started by its own PID (the gains of the controller
YAML, as the running robot would hold them).

    loop.reset(q0)             put the tuned joint at q0 (zero velocity), the others at their start
    loop.step(effort) -> (t, q, qd)   one time step with that effort on the tuned joint
    loop.dt, loop.effort_limit, loop.joint_name, loop.lower, loop.upper
"""
import math

from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.tuning import TuningError


def _clamp(v, lim):
    if lim is None or lim <= 0:
        return v
    return max(-lim, min(lim, v))


class IntegratorLoop(object):
    """One joint I q'' = u - b q' - G sin q, no ODE (for tests and quick looks)."""

    def __init__(self, inertia=0.1, damping=0.0, gravity_torque=0.0, effort_limit=None, dt=0.001,
                 name="joint", lower=None, upper=None):
        from modrob_sim.ros_control.testing import IntegratorJoint
        self.dt = dt
        self.joint_name = name
        self.effort_limit = effort_limit
        self.lower, self.upper = lower, upper
        self._make = lambda q0: IntegratorJoint(name, "revolute", inertia, damping, lower, upper,
                                                effort_limit, None, q0, gravity_torque)
        self.reset(0.0)

    def reset(self, q0):
        self.joint = self._make(q0)
        self.t = 0.0

    def step(self, effort):
        self.joint.set_effort(effort)
        self.joint.step(self.dt)
        self.t += self.dt
        return self.t, self.joint.position, self.joint.velocity


class PhysicsLoop(object):
    """A joint of a URDF robot in the ODE physics core (modrob_sim.physics), gravity on.

    urdf_xml: the robot; joint_name: the joint to tune; start: {joint: position} for the robot's
    configuration (others default to 0); hold_gains: {joint: {p, i, d, i_clamp}} for the joints
    that are held (missing ones are held with stiff default gains); world_sdf: optional extra world.
    """

    def __init__(self, urdf_xml, joint_name, start=None, hold_gains=None, dt=0.001, resource_resolver=None):
        from modrob_sim.physics import World
        self.dt = dt
        self.urdf_xml = urdf_xml
        self.world = World(time_step=dt, resource_resolver=resource_resolver)
        self.model = self.world.add_urdf("robot", urdf_xml, joint_positions=dict(start or {}))
        movable = {n: j for n, j in self.model.joints.items()
                   if j.type in ("revolute", "continuous", "prismatic") and getattr(j, "mimic", None) is None}
        if joint_name not in movable:
            raise TuningError("the robot has no movable joint '%s'; its joints are: %s"
                              % (joint_name, ", ".join(sorted(movable))))
        self.joint_name = joint_name
        self.joint = movable[joint_name]
        self.effort_limit = self.joint.effort_limit
        self.lower, self.upper = self.joint.lower, self.joint.upper
        self.start = {n: float((start or {}).get(n, 0.0)) for n in movable}
        self.holds = {}
        for n, j in movable.items():
            if n == joint_name:
                continue
            g = (hold_gains or {}).get(n)
            if g is None:
                g = {"p": 2000.0, "d": 50.0, "i": 0.0}
            clamp = abs(g.get("i_clamp", 0.0))
            gains = PidGains(g.get("p", 0.0), g.get("i", 0.0), g.get("d", 0.0), clamp, -clamp,
                             g.get("antiwindup", False))
            self.holds[n] = (j, Pid(gains))
        self.reset(self.start[joint_name])

    def reset(self, q0):
        self.world.reset()
        names = list(self.start)
        positions = [q0 if n == self.joint_name else self.start[n] for n in names]
        self.model.set_configuration(names, positions)
        for j, pid in self.holds.values():
            pid.reset()
        self.t = 0.0

    def step(self, effort):
        dt = self.dt
        for n, (j, pid) in self.holds.items():
            u = pid.compute(self.start[n] - j.position, dt)
            j.set_effort(_clamp(u, j.effort_limit))
        if not math.isfinite(effort):
            raise TuningError("non-finite effort %r for joint '%s'" % (effort, self.joint_name))
        self.joint.set_effort(_clamp(effort, self.effort_limit))
        self.world.step()
        events = self.world.pop_events()
        if events:
            raise TuningError("the simulation blew up while tuning '%s': %s" % (self.joint_name, events[0]))
        self.t += dt
        return self.t, self.joint.position, self.joint.velocity
