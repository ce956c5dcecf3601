"""RobotHWSim: gazebo_ros_control's DefaultRobotHWSim over the physics core's Joint handles.

For each transmission joint it offers a joint state (position, velocity, effort) and the command
interfaces its ``<transmission>`` tags name (effort, position, velocity): one or several, from
several ``<hardwareInterface>`` elements of one transmission or from several transmissions of the
same joint (franka_description gives each arm joint three). One of them is active at a time:
the first declared until a controller claiming another one is started (``do_switch``, ros_control's
RobotHW::doSwitch), as franka_gazebo's FrankaHWSim switches. ``write(dt)`` applies the active
interface's command as Gazebo does:

=============  ==========================================================================
EFFORT         command clamped to +-effort limit, applied as joint effort
POSITION       no ``pid_gains/<joint>``: the joint is set kinematically to the command
               (rate-limited by the velocity limit, clamped to [lower, upper]) at every step,
               by its actuator (OUT_POSITION)
POSITION_PID   with ``pid_gains/<joint>``: effort = clamp(PID(position error), +-effort limit);
               continuous joints take the shortest angular way
VELOCITY       no gains: ODE joint motor to the command with max force = effort limit
               (a controller's PID may drive it at every step: an OUT_VELOCITY actuator)
VELOCITY_PID   with gains: effort = clamp(PID(velocity error), +-effort limit)
=============  ==========================================================================

Limits come from the URDF (through the Joint handle). Differences from Gazebo, on purpose: a
position command starts at the joint's spawn position (Gazebo starts at 0 and snaps the joint
there); non-finite commands are never passed to ODE (it would abort the process); a joint with
several interfaces is one joint (Gazebo's DefaultRobotHWSim keeps only the first interface of a
transmission and would register a joint named by three transmissions three times).

The efforts are applied by the joint's actuator (modrob_sim.physics.actuators): with a ``world``
the World's own, which it runs at every step, between two updates too (an idle effort joint keeps
its last command, a PID its target; an effort joint that has had no effort has no actuator, so a
model plugin may drive it with its own, as the Katana's gripper plugin drives its fingers);
without one (a test plant, a script that steps joints itself) ``write`` runs them. A controller
that needs another actuator kind (a PID to a position, a trajectory segment) takes the joint's
actuator with :meth:`JointResource.actuate` and hands it back with :meth:`JointResource.release`;
the hardware's write leaves a taken joint alone.
"""
import math

from modrob_sim.errors import ControllerError
from modrob_sim.physics import actuators
from modrob_sim.physics.backends import PureBackend
from modrob_sim.ros_control import angles
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.transmissions import (EFFORT, POSITION, VELOCITY, canonical_interface)

POSITION_PID = "POSITION_PID"
VELOCITY_PID = "VELOCITY_PID"


def _limit(value):
    return None if value is None else float(value)


class JointResource(object):
    """One simulated joint as ros_control sees it: state read each update, the command
    interfaces it offers (``interfaces``, declaration order), the active one (``interface``,
    ``method``), its command, and the actuator that applies it (``actuator``; ``owner`` is the
    controller that took it, or None)."""

    def __init__(self, sim_joint, interface, world=None, warn=None):
        """``interface``: one interface name or a sequence of them (the first is active).
        ``warn(msg)``: where warnings go."""
        self.sim = sim_joint
        self._world = world
        self.warn = warn or (lambda msg: None)
        self._warned_foreign = False
        self.actuator = None
        self.owner = None
        self.synced_gains = None
        self.name = sim_joint.name
        self.type = sim_joint.type
        self.interfaces = (interface,) if isinstance(interface, str) else tuple(interface)
        self.interface = self.interfaces[0]
        self.lower = _limit(getattr(sim_joint, "lower", None))
        self.upper = _limit(getattr(sim_joint, "upper", None))
        if self.type == "continuous":
            self.lower = self.upper = None
        self._effort_limit = _limit(getattr(sim_joint, "effort_limit", None))
        vl = _limit(getattr(sim_joint, "velocity_limit", None))
        self.velocity_limit = vl if vl is not None and vl > 0.0 else None
        self.position = float(sim_joint.position)
        self.velocity = float(sim_joint.velocity)
        self.effort = 0.0
        self.command = self.position if self.interface == POSITION else 0.0
        self.method = self.interface
        self.pid = None
        self.pid_source = None
        self._prev_position_cmd = None

    def set_pid(self, pid, source):
        """The ``gazebo_ros_control/pid_gains/<joint>`` PID: position and velocity commands go
        through it from now on."""
        self.pid, self.pid_source = pid, source
        self.method = self._method(self.interface)
        self.hardware_actuator()

    def _method(self, interface):
        if self.pid is not None and interface == POSITION:
            return POSITION_PID
        if self.pid is not None and interface == VELOCITY:
            return VELOCITY_PID
        return interface

    def select(self, interface):
        """Make ``interface`` (one of ``interfaces``) the active one. A change starts its command
        from rest: the current position for the position interface, 0 for effort and velocity;
        the PID and the position rate limit start afresh. Returns True when it changed."""
        if interface not in self.interfaces:
            raise ControllerError("joint '%s' offers %s, not hardware_interface/%s"
                                  % (self.name, self.offered(), interface))
        if interface == self.interface:
            return False
        if self.method == VELOCITY:
            self.sim.set_velocity_target(0.0, 0.0)      # the joint motor holds on until released
        self.interface = interface
        self.method = self._method(interface)
        self.command = self.position if interface == POSITION else 0.0
        self._prev_position_cmd = None
        if self.pid is not None:
            self.pid.reset()
        if self.owner is None:
            self.hardware_actuator()
        return True

    def offered(self):
        return ", ".join("hardware_interface/" + i for i in self.interfaces)

    @property
    def effort_limit(self):
        """The hardware's effort clamp (the URDF's <limit effort>); the actuator applies it."""
        return self._effort_limit

    @effort_limit.setter
    def effort_limit(self, limit):
        self._effort_limit = _limit(limit)
        if self.actuator is not None:
            self.actuator.effort_limit = self._effort_limit

    @property
    def has_position_limits(self):
        return self.lower is not None and self.upper is not None and self.type in ("revolute", "prismatic")

    def clamp_position(self, q):
        if self.has_position_limits:
            return min(max(q, self.lower), self.upper)
        return q

    def clamp_effort(self, e):
        if self.effort_limit is None:
            return e
        return min(max(e, -self.effort_limit), self.effort_limit)

    @property
    def position_rule(self):
        """The error rule of a position PID on this joint (actuators.PLAIN, CLAMPED, SHORTEST):
        the shortest way on a continuous joint, the target clamped into a revolute joint's travel."""
        if self.type == "continuous":
            return actuators.SHORTEST
        if self.type == "revolute" and self.has_position_limits:
            return actuators.CLAMPED
        return actuators.PLAIN

    def position_error(self, target):
        return actuators.position_error(self.position_rule, target, self.position, self.lower, self.upper)

    # ---- the velocity interface's ODE motor ------------------------------------------------------
    def motor_force(self):
        """The force bound of the velocity interface's motor: the effort limit (Gazebo's "fmax"),
        1e6 without one."""
        return self.effort_limit if self.effort_limit is not None else 1e6

    def apply_velocity(self, cmd):
        """DefaultRobotHWSim's write of a velocity command without pid_gains: the joint's ODE
        motor to ``cmd`` (0 when not finite), clamped to +-velocity limit, with motor_force()."""
        if not math.isfinite(cmd):
            cmd = 0.0
        if self.velocity_limit is not None:
            cmd = min(max(cmd, -self.velocity_limit), self.velocity_limit)
        self.sim.set_velocity_target(cmd, self.motor_force())

    def can_drive(self, output):
        """True when a controller may write ``output`` (actuators.OUT_EFFORT, OUT_VELOCITY,
        OUT_POSITION) through the joint's actuator, as the active interface would take it: an
        effort joint's effort, the motor of a velocity joint without pid_gains (one with pid_gains
        puts its own PID after the controller's: that chain runs in Python at every update), the
        kinematic set-point of a position joint without pid_gains (in a World: a test plant sets
        its joint itself)."""
        if output == actuators.OUT_EFFORT:
            return self.method == EFFORT
        if output == actuators.OUT_POSITION:
            return self.method == POSITION and self._world is not None
        return output == actuators.OUT_VELOCITY and self.method == VELOCITY and self.motor_force() > 0.0

    # ---- the joint's actuator ------------------------------------------------------------------
    def actuate(self, kind, gains=None, error=actuators.PLAIN, owner=None, output=actuators.OUT_EFFORT):
        """The joint's actuator, switched to ``kind`` (its PID state from zero) with ``gains`` and
        the position error rule ``error``; ``owner`` (a controller) takes it: the hardware's write
        leaves it alone until :meth:`release`. ``output`` OUT_VELOCITY: the output is the velocity
        interface's command, applied as :meth:`apply_velocity` applies it, at every step."""
        a = self.actuator
        if a is None:
            if self._world is not None:
                a = self._world.add_actuator(self.sim, kind)
            else:
                a = actuators.Actuator(None, PureBackend, self.sim, kind, actuators.PyRecord(kind))
                if hasattr(self.sim, "bind_actuator"):      # a physics Joint reports its effort
                    self.sim.bind_actuator(a)
            self.actuator = a
        elif a.kind != kind:
            a.kind = kind
        a.reset()
        a.error = error
        if gains is not None:
            a.gains = gains
        a.effort_limit = self.effort_limit
        a.output = output
        if output == actuators.OUT_VELOCITY:
            a.velocity_limit = self.velocity_limit
            a.max_force = self.motor_force()
        elif output == actuators.OUT_POSITION:
            # the hardware's PositionJointSaturationHandle, at every step, from where the joint is
            a.velocity_limit = self.velocity_limit
            a.hold_position()
        self.owner = owner
        return a

    def hardware_actuator(self):
        """The actuator through which the hardware applies the active interface's command:
        an effort joint's held effort, the pid_gains PIDs (DefaultRobotHWSim's position and
        velocity PIDs), a position joint's kinematic set-point (OUT_POSITION: set at every step,
        as Gazebo's writeSim sets it); none for an ODE motor's velocity joint."""
        m = self.method
        if m == EFFORT:
            cmd = self.command if math.isfinite(self.command) else 0.0
            if self.actuator is not None or self.needs_effort_actuator(cmd):
                self.actuate(actuators.EFFORT).command = cmd
        elif m == POSITION_PID:
            self.actuate(actuators.POSITION_PID, self.pid.gains, self.position_rule).command = self.position
        elif m == VELOCITY_PID:
            self.actuate(actuators.VELOCITY_PID, self.pid.gains)
        elif m == POSITION and self.can_drive(actuators.OUT_POSITION):
            self.actuate(actuators.EFFORT, error=self.position_rule,
                         output=actuators.OUT_POSITION).command = self.command
        else:
            self.remove_actuator()
        self.synced_gains = self.pid.gains if self.pid is not None else None

    def needs_effort_actuator(self, effort):
        """True when the hardware must take an actuator to hold ``effort`` on an effort joint that
        has none. A zero effort needs none: the joint stays free for a plugin's own actuator
        (katana_gazebo_plugins' gripper drives finger joints that also have effort
        transmissions; in Gazebo both call SetForce, and the forces add). A non-zero effort on a
        joint another plugin's actuator drives is not applied, with a warning once."""
        if effort == 0.0:
            return False
        other = getattr(self.sim, "actuator", None)
        if other is None:
            return True
        if not self._warned_foreign:
            self._warned_foreign = True
            self.warn("joint '%s': its effort command (%g) is not applied while %r drives the joint "
                      "(Gazebo would add the two); stop one of them" % (self.name, effort, other))
        return False

    def release(self):
        """A controller lets the joint go: the hardware applies the active interface's command
        again (an effort joint keeps the last effort, a velocity joint its motor at the last
        velocity, as ros_control's hardware does)."""
        self.owner = None
        self.hardware_actuator()
        if self.method == VELOCITY:
            self.apply_velocity(self.command)

    def remove_actuator(self):
        """No actuator on the joint (its interface needs none, or the hardware goes)."""
        a, self.actuator = self.actuator, None
        self.owner = None
        if a is None:
            return
        if self._world is not None:
            if a in self._world.actuators:
                self._world.remove_actuator(a)
        elif hasattr(self.sim, "bind_actuator"):
            self.sim.bind_actuator(None)


class RobotHWSim(object):
    """The hardware of one model: ``joints`` (name -> JointResource) in transmission order."""

    def __init__(self, model_joints, transmissions, pid_gains=None, warn=None, world=None):
        """``model_joints``: name -> physics Joint. ``transmissions``: TransmissionInfo list.
        ``pid_gains``: Params of the ``gazebo_ros_control/pid_gains`` namespace (or None).
        ``warn(msg)``: where warnings go (deprecated syntax, skipped transmissions).
        ``world``: the World of the joints, whose actuators then apply the efforts at every step;
        None: :meth:`write` applies them (a plant stepped by its caller)."""
        warn = warn or (lambda msg: None)
        self.joints = {}
        self.order = []
        self.notes = []
        self.world = world
        #: the update's physics step count (ControllerManager.update sets it): controllers that
        #: decimate by updates count with it, also across the steps the World made natively
        self.iteration = -1
        offered = {}            # joint name -> [interface, ...] in declaration order
        for tr in transmissions:
            if not tr.joints:
                warn("Transmission %s has no associated joints: ignored." % tr.name)
                continue
            if len(tr.joints) > 1:
                warn("Transmission %s has more than one joint; DefaultRobotHWSim supports one: ignored."
                     % tr.name)
                continue
            tj = tr.joints[0]
            ifaces = tj.interfaces
            if not ifaces and tr.actuators and tr.actuators[0].interfaces:
                ifaces = tr.actuators[0].interfaces
                warn("The <hardwareInterface> element of transmission %s should be nested inside the <joint> "
                     "element, not <actuator>; it is used anyway." % tr.name)
            if not ifaces:
                warn("Joint %s of transmission %s does not specify any hardware interface: not added to the "
                     "robot hardware simulation." % (tj.name, tr.name))
                continue
            canonical = []
            for text in ifaces:
                iface = canonical_interface(text)
                if iface is None:
                    raise ControllerError("Transmission %s: no matching hardware interface found for '%s' "
                                          "of joint %s (use hardware_interface/EffortJointInterface, "
                                          "PositionJointInterface or VelocityJointInterface)"
                                          % (tr.name, text, tj.name))
                canonical.append(iface)
            if tj.name not in model_joints:
                raise ControllerError("Transmission %s names joint '%s', which is not in the model "
                                      "(joints: %s)"
                                      % (tr.name, tj.name, ", ".join(sorted(model_joints))))
            jtype = getattr(model_joints[tj.name], "type", "revolute")
            if jtype not in ("revolute", "continuous", "prismatic"):
                warn("Transmission %s: joint %s is %s; only revolute, continuous and prismatic joints can be "
                     "actuated: ignored." % (tr.name, tj.name, jtype))
                continue
            if tj.name not in offered:
                offered[tj.name] = []
                self.order.append(tj.name)
            for iface in canonical:
                if iface in offered[tj.name]:
                    warn("Joint %s: hardware_interface/%s is declared twice (transmission %s); once is "
                         "enough." % (tj.name, iface, tr.name))
                else:
                    offered[tj.name].append(iface)
            for act in tr.actuators:
                if act.reduction != 1.0:
                    self.notes.append("Transmission %s: mechanicalReduction %g is ignored, as "
                                      "gazebo_ros_control's DefaultRobotHWSim does (commands are joint "
                                      "values)"
                                      % (tr.name, act.reduction))
        for name in self.order:
            ifaces = offered[name]
            res = JointResource(model_joints[name], ifaces, world, warn)
            if (POSITION in ifaces or VELOCITY in ifaces) and pid_gains is not None and pid_gains.has(name):
                res.set_pid(Pid(PidGains.from_params(pid_gains.child(name))), pid_gains.path(name))
            else:
                res.hardware_actuator()
            self.joints[name] = res

    def joint(self, name, interface=None, controller=""):
        """The JointResource for a controller; ControllerError naming the joint and interface."""
        res = self.joints.get(name)
        if res is None:
            raise ControllerError("%sjoint '%s' is not a ros_control joint of this robot: it needs a "
                                  "<transmission> (known joints: %s)"
                                  % (("controller '%s': " % controller) if controller else "", name,
                                     ", ".join(self.order) or "none"))
        if interface is not None and interface not in res.interfaces:
            raise ControllerError("%sjoint '%s' offers %s (from its <transmission>), "
                                  "not hardware_interface/%s that this controller type needs"
                                  % (("controller '%s': " % controller) if controller else "", name,
                                     res.offered(), interface))
        return res

    def do_switch(self, start, stop):
        """ros_control's RobotHW::doSwitch, before the controllers in ``stop`` stop and those in
        ``start`` start (both lists of controllers): each joint a starting controller claims
        through a command interface gets that interface active. A joint nobody claims afterwards
        keeps its interface and last command, as in Gazebo."""
        for c in start:
            for cpp_name, joints in c.claimed_resources:
                iface = canonical_interface(cpp_name)
                if iface is None:
                    continue
                for j in joints:
                    self.joints[j].select(iface)

    def read(self):
        for name in self.order:
            res = self.joints[name]
            j = res.sim
            res.position = float(j.position)
            res.velocity = float(j.velocity)
            res.effort = float(j.effort)

    @property
    def needs_every_update(self):
        """True when the hardware's write has work at the next step although no controller
        updates: a position joint moved kinematically without an actuator (a test plant), a
        pid_gains position joint whose command is still rate-limited towards its target
        (the velocity limit moves it by one step's worth per write), or the pid_gains of a joint
        the hardware drives changed (a joint a controller or the hardware's subclass owns gets its
        gains from that owner, as in write). Then the next step is an update in Python; otherwise
        the actuators (held efforts, pid_gains PIDs) and the ODE motors carry the last write."""
        for res in self.joints.values():
            m = res.method
            if m == POSITION and res.actuator is None:
                return True
            if m == POSITION_PID and res.owner is None and not self._position_settled(res):
                return True
            if res.owner is None and res.pid is not None and res.pid.gains is not res.synced_gains and \
                    res.actuator is not None:
                return True
        return False

    @staticmethod
    def _position_settled(res):
        """True when the next write of a pid_gains position joint would give its actuator the
        target it already has (the rate limit has reached the command)."""
        prev = res._prev_position_cmd
        if prev is None:
            return False
        cmd = res.command
        if not math.isfinite(cmd):
            return False
        if res.type == "continuous":
            return prev + angles.shortest_angular_distance(prev, cmd) == prev
        return res.clamp_position(cmd) == prev

    def reset_commands(self):
        """After a reset: hold where the joints are now, PIDs cleared."""
        self.read()
        for res in self.joints.values():
            res.command = res.position if res.interface == POSITION else 0.0
            res._prev_position_cmd = None
            if res.pid is not None:
                res.pid.reset()
            if res.owner is None:
                res.hardware_actuator()

    def write(self, dt, t=0.0):
        for name in self.order:
            res = self.joints[name]
            if res.owner is not None:
                continue        # a controller drives the joint's actuator itself
            cmd = res.command
            if not math.isfinite(cmd):
                cmd = res.position if res.interface == POSITION else 0.0
            m = res.method
            if res.pid is not None and res.pid.gains is not res.synced_gains and res.actuator is not None:
                res.synced_gains = res.pid.gains        # gains changed (dynamic_reconfigure)
                res.actuator.gains = res.synced_gains
            if m == EFFORT:
                if res.actuator is None:
                    if not res.needs_effort_actuator(cmd):
                        continue
                    res.actuate(actuators.EFFORT)
                res.actuator.command = cmd          # the actuator clamps to the effort limit
            elif m == POSITION and res.actuator is not None:
                res.actuator.command = cmd          # it saturates and sets the joint at every step
            elif m in (POSITION, POSITION_PID):
                cmd = self._saturate_position(res, cmd, dt)
                if m == POSITION:
                    res.sim.set_position(cmd)
                else:
                    res.actuator.command = cmd
            elif m == VELOCITY:
                res.apply_velocity(cmd)
            elif m == VELOCITY_PID:
                if res.velocity_limit is not None:
                    cmd = min(max(cmd, -res.velocity_limit), res.velocity_limit)
                res.actuator.command = cmd
        if self.world is None:      # no World to run the actuators: this update does
            actuated = [(res.actuator.record, res.sim) for res in (self.joints[n] for n in self.order)
                        if res.actuator is not None]
            actuators.apply_python(actuated, t, dt)

    def remove_actuators(self):
        """The hardware goes (its model's plugin shuts down): its joints are free again."""
        for res in self.joints.values():
            res.remove_actuator()

    @staticmethod
    def _saturate_position(res, cmd, dt):
        """joint_limits_interface::PositionJointSaturationHandle: rate limit by the velocity
        limit relative to the previous command, clamp to the position limits."""
        prev = res._prev_position_cmd
        if prev is None:
            prev = res.position
        rule = actuators.SHORTEST if res.type == "continuous" else actuators.PLAIN
        lo, hi = (res.lower, res.upper) if res.has_position_limits else (-math.inf, math.inf)
        vl = res.velocity_limit if res.velocity_limit is not None else math.inf
        cmd = actuators.saturate_position(rule, prev, cmd, vl, dt, lo, hi)
        res._prev_position_cmd = cmd
        return cmd

    def pid_joints(self):
        """Joints driven by a pid_gains PID: name -> JointResource."""
        return {n: r for n, r in self.joints.items() if r.pid is not None}


def pid_gains_params(values, ns):
    return Params(values, ns)
