"""Parse one line typed into ``motion_terminal`` into a command object.

    0.1 0.5 -0.3 ...     joint angles (rad; commas allowed), one per arm joint
    deg 10 45 -20 ...    the same in degrees
    #1                   control robot 1 from now on
    home                 every arm joint to its home angle
    open / close         the gripper
    xyz 0.4 0.1 1.3      move the end effector to a point (metres, world frame), by KDL IK
    state                show the robot's joint angles (commanded and measured)
    help                 this table
    quit                 leave the terminal

Every error is a :class:`ParseError` whose message is one line, fit to show the user.
"""
import math

from modrob_motion.errors import ParseError

HELP_TABLE = (
    ("0.1 0.5 -0.3 ...", "joint angles in rad, one per arm joint (commas allowed)"),
    ("deg 10 45 -20 ...", "joint angles in degrees"),
    ("#<id>", "switch to robot <id> (e.g. #1)"),
    ("home", "all arm joints to their home angles"),
    ("open | close", "open or close the gripper"),
    ("xyz <x> <y> <z>", "end effector to a point in the world frame (m), solved by KDL IK"),
    ("state", "show commanded and measured joint angles"),
    ("help", "this table"),
    ("quit", "leave (Ctrl-D works too)"),
)


def help_text():
    width = max(len(k) for k, _ in HELP_TABLE)
    return "\n".join("  %-*s  %s" % (width, k, v) for k, v in HELP_TABLE)


class Command(object):
    """Base of the parsed commands; equality by type and fields (handy in tests)."""
    __slots__ = ()

    def _fields(self):
        return tuple(getattr(self, s) for s in self.__slots__)

    def __eq__(self, other):
        return type(self) is type(other) and self._fields() == other._fields()

    def __ne__(self, other):
        return not self == other

    def __hash__(self):
        return hash((type(self).__name__,) + self._fields())

    def __repr__(self):
        return "%s(%s)" % (type(self).__name__, ", ".join(repr(f) for f in self._fields()))


class JointTarget(Command):
    __slots__ = ("positions",)

    def __init__(self, positions):
        self.positions = tuple(positions)


class SelectRobot(Command):
    __slots__ = ("robot_id",)

    def __init__(self, robot_id):
        self.robot_id = robot_id


class CartesianTarget(Command):
    __slots__ = ("xyz",)

    def __init__(self, xyz):
        self.xyz = tuple(xyz)


class GripperCommand(Command):
    __slots__ = ("action",)

    def __init__(self, action):
        self.action = action


class Home(Command):
    __slots__ = ()


class Help(Command):
    __slots__ = ()


class State(Command):
    __slots__ = ()


class Quit(Command):
    __slots__ = ()


KEYWORDS = {"home": Home, "help": Help, "?": Help, "h": Help, "state": State, "status": State,
            "quit": Quit, "exit": Quit, "q": Quit}


def _number(token):
    try:
        value = float(token)
    except ValueError:
        raise ParseError("'%s' is neither a number nor a command (type help)" % token)
    if not math.isfinite(value):
        raise ParseError("'%s' is not a finite number" % token)
    return value


def parse_line(line):
    """Returns a Command, or None for a blank line. Raises ParseError."""
    if line is None:
        return Quit()
    text = line.strip()
    if not text:
        return None
    if text.startswith("#"):
        rest = text[1:].strip()
        if not rest.isdigit():
            raise ParseError("'%s': a robot is chosen by its number, for example #1" % text)
        return SelectRobot(int(rest))
    tokens = text.replace(",", " ").split()
    head = tokens[0].lower()
    if head in KEYWORDS:
        if len(tokens) > 1:
            raise ParseError("'%s' takes no arguments" % head)
        return KEYWORDS[head]()
    if head in ("open", "close"):
        if len(tokens) > 1:
            raise ParseError("'%s' takes no arguments" % head)
        return GripperCommand(head)
    if head == "xyz":
        if len(tokens) != 4:
            raise ParseError("xyz needs three numbers (metres, world frame), e.g. xyz 0.4 0.1 1.3")
        return CartesianTarget(_number(t) for t in tokens[1:])
    if head in ("deg", "degrees"):
        if len(tokens) < 2:
            raise ParseError("deg needs joint angles in degrees, e.g. deg 10 45 -20")
        return JointTarget(math.radians(_number(t)) for t in tokens[1:])
    return JointTarget(_number(t) for t in tokens)
