"""The motion terminal's behaviour, without ROS: lines in, replies and joint commands out.

A ``MotionTerminal`` holds the robot being controlled and the last command sent to each robot.
Robots are found through a *directory* (``get(robot_id) -> RobotInfo | None`` and ``ids()``),
Cartesian targets through an *IK solver* ``solve(robot_info, xyz, seed) -> positions`` that raises
MotionError when the point cannot be reached. Nothing here raises on a bad line: every problem
becomes a one-line reply.
"""
from modrob_motion.errors import MotionError
from modrob_motion.joint_matching import JointCommandMatcher
from modrob_motion import terminal_parser as tp


class JointCommand(object):
    """A JointState to send: robot_id, joint names, positions."""

    def __init__(self, robot_id, names, positions):
        self.robot_id = robot_id
        self.names = list(names)
        self.positions = [float(p) for p in positions]

    def __repr__(self):
        return "JointCommand(%d, %r, %r)" % (self.robot_id, self.names, self.positions)


class Reply(object):
    """What handling a line produced: text for the user, an optional command, quit flag, ok flag."""

    def __init__(self, text="", command=None, quit=False, ok=True):
        self.text = text
        self.command = command
        self.quit = quit
        self.ok = ok

    def __repr__(self):
        return "Reply(%r, %r, quit=%r, ok=%r)" % (self.text, self.command, self.quit, self.ok)


class DictDirectory(object):
    """A fixed set of robots: ``{robot_id: RobotInfo}``."""

    def __init__(self, robots):
        self.robots = dict(robots)

    def get(self, robot_id):
        return self.robots.get(robot_id)

    def ids(self):
        return sorted(self.robots)


def _fmt(values):
    return " ".join("%.3f" % v for v in values)


class MotionTerminal(object):

    def __init__(self, directory, robot_id=0, ik_solver=None, measured=None):
        """measured: optional callable robot_id -> {joint: position} (the latest joint states)."""
        self.directory = directory
        self.robot_id = robot_id
        self.ik_solver = ik_solver
        self.measured = measured
        self.last_command = {}      # robot_id -> {joint: position}

    def prompt(self):
        return "modrob%d> " % self.robot_id

    def handle(self, line):
        try:
            cmd = tp.parse_line(line)
        except MotionError as exc:
            return Reply(str(exc), ok=False)
        if cmd is None:
            return Reply("")
        try:
            return self._dispatch(cmd)
        except MotionError as exc:
            return Reply(str(exc), ok=False)

    # -- commands ---------------------------------------------------------------------------
    def _robot(self, robot_id=None):
        rid = self.robot_id if robot_id is None else robot_id
        info = self.directory.get(rid)
        if info is None:
            known = self.directory.ids()
            where = ("; robots here: " + ", ".join("#%d" % i for i in known)) if known else \
                "; no robot is running yet"
            raise MotionError("no robot %d%s" % (rid, where))
        return info

    def _send(self, info, names, positions, what):
        matcher = JointCommandMatcher(info.all_joints, info.limits, robot="modrob%d" % info.robot_id)
        values = matcher.match(names, positions)
        self.last_command.setdefault(info.robot_id, {}).update(values)
        cmd = JointCommand(info.robot_id, list(values.keys()), list(values.values()))
        return Reply("modrob%d: %s" % (info.robot_id, what), command=cmd)

    def _dispatch(self, cmd):
        if isinstance(cmd, tp.Help):
            return Reply(tp.help_text())
        if isinstance(cmd, tp.Quit):
            return Reply("bye", quit=True)
        if isinstance(cmd, tp.SelectRobot):
            info = self._robot(cmd.robot_id)
            self.robot_id = cmd.robot_id
            return Reply("now controlling modrob%d (%d arm joints: %s%s)" % (
                cmd.robot_id, len(info.arm_joints), ", ".join(info.arm_joints),
                "; gripper" if info.gripper else ""))
        info = self._robot()
        if isinstance(cmd, tp.JointTarget):
            if len(cmd.positions) != len(info.arm_joints):
                raise MotionError("modrob%d has %d arm joints (%s); got %d angles"
                                  % (info.robot_id, len(info.arm_joints), ", ".join(info.arm_joints),
                                     len(cmd.positions)))
            return self._send(info, info.arm_joints, cmd.positions, "joints -> " + _fmt(cmd.positions))
        if isinstance(cmd, tp.Home):
            return self._send(info, info.arm_joints, info.home, "home -> " + _fmt(info.home))
        if isinstance(cmd, tp.GripperCommand):
            if info.gripper is None:
                raise MotionError("modrob%d has no gripper (build it with --gripper)" % info.robot_id)
            target = info.gripper.command(cmd.action)
            names = list(target.keys())
            return self._send(info, names, [target[n] for n in names], "gripper " + cmd.action)
        if isinstance(cmd, tp.CartesianTarget):
            if self.ik_solver is None:
                raise MotionError("xyz needs the KDL IK solver, which is not available here")
            seed = self._seed(info)
            q = self.ik_solver(info, cmd.xyz, seed)
            return self._send(info, info.arm_joints, q, "xyz %s -> joints %s" % (_fmt(cmd.xyz), _fmt(q)))
        if isinstance(cmd, tp.State):
            return Reply(self._state_text(info))
        raise MotionError("command %r is not handled" % (cmd,))   # pragma: no cover

    def _seed(self, info):
        """IK seed: measured angles if known, else the last command, else home."""
        meas = self.measured(info.robot_id) if self.measured else None
        last = self.last_command.get(info.robot_id, {})
        seed = []
        for j, h in zip(info.arm_joints, info.home):
            if meas and j in meas:
                seed.append(meas[j])
            else:
                seed.append(last.get(j, h))
        return seed

    def _state_text(self, info):
        last = self.last_command.get(info.robot_id, {})
        meas = (self.measured(info.robot_id) if self.measured else None) or {}
        rows = ["modrob%d  %-24s %10s %10s" % (info.robot_id, "joint", "commanded", "measured")]
        for j in info.all_joints:
            c = "%.4f" % last[j] if j in last else "-"
            m = "%.4f" % meas[j] if j in meas else "-"
            rows.append("         %-24s %10s %10s" % (j, c, m))
        return "\n".join(rows)
