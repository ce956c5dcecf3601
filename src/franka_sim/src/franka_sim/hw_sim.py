"""``franka_gazebo/FrankaHWSim``: the Franka arm's hardware as franka_gazebo simulates it (pure).

What it adds to gazebo_ros_control's DefaultRobotHWSim:

- only SimpleTransmissions of the arm's joints (``<arm_id>_joint1..7``) and fingers
  (``<arm_id>_finger_joint1/2``) count; the ``franka_hw/FrankaStateInterface`` and
  ``FrankaModelInterface`` transmissions name the resources ``<arm_id>_robot`` and
  ``<arm_id>_model`` that the Franka controllers claim;
- the position and velocity interfaces run franka's "motion generators": a PID per joint with the
  gains of ``motion_generators/position/gains/<joint>`` and ``motion_generators/velocity/gains/
  <joint>``, the effort clamped to the joint's limit;
- an arm joint that no running controller commands holds the position it had when its last
  controller stopped (at start: the spawn pose), with the position gains, as the robot does in
  its idle mode (a position PID actuator of the World, at every physics step);
- gravity is compensated, as the robot's own controller does: the arm's moving links (everything
  below ``<arm_id>_joint1``) are simulated without gravity, which for a fixed base is the same as
  adding the gravity torque g(q) to every arm joint, and holds at every physics step; loads the
  arm carries (a grasped object) still weigh on it;
- ``initialized`` (the ROS side publishes it) becomes true at the first update, as the
  ``spawner --wait-for initialized`` of franka_gazebo's launch files waits for.

Finger joints are effort-driven (by the franka_gazebo/FrankaGripperSim controller).
"""
from modrob_sim.errors import ControllerError
from modrob_sim.physics import actuators
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.transmissions import EFFORT, POSITION, VELOCITY, canonical_interface

SIM_TYPE = "franka_gazebo/FrankaHWSim"
ARM_SUFFIXES = tuple("_joint%d" % i for i in range(1, 8))
FINGER_SUFFIXES = ("_finger_joint1", "_finger_joint2")
SIMPLE = "transmission_interface/SimpleTransmission"
STATE_INTERFACE = "franka_hw/FrankaStateInterface"
MODEL_INTERFACE = "franka_hw/FrankaModelInterface"


def arm_link_subtree(model_joints, arm_id):
    """Names of the links below ``<arm_id>_joint1`` (the arm's moving links, hand and fingers)."""
    first = model_joints.get(arm_id + "_joint1")
    if first is None:
        return []
    children = {}
    for j in model_joints.values():
        children.setdefault(j.parent, []).append(j.child)
    out, todo = [], [first.child]
    while todo:
        link = todo.pop()
        out.append(link)
        todo.extend(children.get(link, ()))
    return out


class FrankaHWSim(RobotHWSim):
    def __init__(self, model, transmissions, arm_id, motion_generators=None, warn=None, world=None):
        """``motion_generators``: Params of the ``motion_generators`` namespace (position/velocity
        gains per joint). ``warn(text)``, ``world`` as RobotHWSim's."""
        warn = warn or (lambda text: None)
        self.arm_id = arm_id
        names = [arm_id + s for s in ARM_SUFFIXES + FINGER_SUFFIXES]
        simple, self.franka_resources = [], {}
        for tr in transmissions:
            if tr.type in (STATE_INTERFACE, MODEL_INTERFACE):
                self.franka_resources[tr.type] = "%s_%s" % (arm_id, "robot" if tr.type == STATE_INTERFACE
                                                            else "model")
                continue
            if tr.type and tr.type != SIMPLE:
                continue
            if len(tr.joints) == 1 and tr.joints[0].name not in names:
                warn("Joint '%s' has a SimpleTransmission (%s) but is not part of the Franka robot "
                     "'%s': FrankaHWSim ignores it" % (tr.joints[0].name, tr.name, arm_id))
                continue
            simple.append(tr)
        super(FrankaHWSim, self).__init__(model.joints, simple, None, warn=warn, world=world)
        self.arm = [arm_id + s for s in ARM_SUFFIXES if arm_id + s in self.joints]
        missing = [arm_id + s for s in ARM_SUFFIXES if arm_id + s not in self.joints]
        if missing:
            raise ControllerError("FrankaHWSim (arm_id '%s'): no transmission for %s; the Franka robot "
                                  "needs its 7 arm joints (is arm_id right? it is read from the "
                                  "parameter arm_id)" % (arm_id, ", ".join(missing)))
        gains = motion_generators or Params({}, "motion_generators")
        self.position_pid, self.velocity_pid, self._pid_source = {}, {}, {}
        for name in self.arm:
            for kind, table in (("position", self.position_pid), ("velocity", self.velocity_pid)):
                ns = gains.child(kind).child("gains")
                table[name] = Pid(PidGains.from_params(ns.child(name))) if ns.has(name) else None
                self._pid_source[table[name]] = ns.path(name)
            self._use_generator(self.joints[name])
        for name, res in self.joints.items():
            if name not in self.arm and EFFORT in res.interfaces:
                res.select(EFFORT)      # fingers: effort, from the gripper controller
        self.claimed = set()          # arm joints commanded by a running controller
        self.stop_position = {}
        self.initialized = False
        self.on_initialized = None    # called once, at the first read (the ROS side publishes it)
        self._hold_pending = True     # the next write takes the idle joints' actuators to hold them
        self._hold_gains = {}         # idle-held joint -> the position generator's gains its actuator has
        self.model = model
        self.gravity_free_links = []
        for link_name in arm_link_subtree(model.joints, arm_id):
            link = model.links.get(link_name)
            if link is not None and link.gravity_enabled:
                link.gravity_enabled = False
                self.gravity_free_links.append(link_name)

    def _use_generator(self, res):
        """The motion generator's PID of the joint's active interface (position or velocity)."""
        pid = self.position_pid[res.name] if res.interface == POSITION else \
            self.velocity_pid[res.name] if res.interface == VELOCITY else None
        if pid is not None:
            pid.reset()
            res.set_pid(pid, self._pid_source[pid])     # its parameters, live-tunable at that path

    # ---- ros_control ------------------------------------------------------------------------
    @property
    def needs_every_update(self):
        return self._hold_pending or self._hold_gains_changed() or super(FrankaHWSim, self).needs_every_update

    def _hold_gains_changed(self):
        """An idle-held joint whose position generator gains changed (dynamic_reconfigure at
        motion_generators/position/gains/<joint>): the next write gives its actuator the new ones."""
        return any(self.joints[j].owner is self and self.position_pid[j].gains is not g
                   for j, g in self._hold_gains.items())

    def do_switch(self, start, stop):
        for c in stop:
            for _iface, joints in c.claimed_resources:
                for j in joints:
                    if j in self.claimed:
                        self.claimed.discard(j)
                        self.stop_position[j] = self.joints[j].position
                        self._hold_pending = True
        super(FrankaHWSim, self).do_switch(start, stop)
        for c in start:
            for cpp_name, joints in c.claimed_resources:
                iface = canonical_interface(cpp_name)
                for j in joints:
                    if j not in self.arm or iface is None:
                        continue
                    if iface in (POSITION, VELOCITY) and \
                            (self.position_pid if iface == POSITION else self.velocity_pid)[j] is None:
                        raise ControllerError("FrankaHWSim: joint %s has no motion_generators/%s/gains/%s "
                                              "(p, i, d) for its %s interface (franka_gazebo's "
                                              "franka_hw_sim.yaml sets them)"
                                              % (j, "position" if iface == POSITION else "velocity", j,
                                                 iface))
                    res = self.joints[j]
                    self.claimed.add(j)
                    res.command = res.position if iface == POSITION else 0.0
                    res._prev_position_cmd = None
                    self._use_generator(res)
                    if res.owner is self:      # the idle hold lets go
                        res.release()

    def read(self):
        super(FrankaHWSim, self).read()
        if not self.initialized:
            for j in self.arm:
                self.stop_position[j] = self.joints[j].position
            self.initialized = True
            if self.on_initialized is not None:
                self.on_initialized()

    def write(self, dt, t=0.0):
        if self._hold_pending:
            # franka's idle mode: an arm joint no controller commands holds its stop position
            # with the position generator's gains (the World's actuator, at every step)
            for j in self.arm:
                res, pid = self.joints[j], self.position_pid[j]
                if j in self.claimed or pid is None:
                    continue
                if res.owner is not self:
                    res.actuate(actuators.POSITION_PID, pid.gains, res.position_rule, owner=self)
                    self._hold_gains[j] = pid.gains
                res.actuator.command = self.stop_position.get(j, res.position)
            self._hold_pending = False
        for j, gains in self._hold_gains.items():
            res, pid = self.joints[j], self.position_pid[j]
            if res.owner is self and pid.gains is not gains:
                res.actuator.gains = self._hold_gains[j] = pid.gains
        super(FrankaHWSim, self).write(dt, t)

    def reset_commands(self):
        for j in self.arm:
            if self.joints[j].owner is self:
                self.joints[j].owner = None
        super(FrankaHWSim, self).reset_commands()
        for j in self.arm:
            self.stop_position[j] = self.joints[j].position
            for pid in (self.position_pid[j], self.velocity_pid[j]):
                if pid is not None:
                    pid.reset()
        self._hold_pending = True

    def resource_names(self, cpp_interface):
        """The resources of a franka_hw interface (``<arm_id>_robot``, ``<arm_id>_model``)."""
        name = self.franka_resources.get(cpp_interface)
        return [name] if name else []
