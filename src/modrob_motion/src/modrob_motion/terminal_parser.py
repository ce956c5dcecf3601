"""Parse one line typed into ``motion_terminal`` into a command object.

:data:`COMMANDS` is the one table of what the terminal understands: :func:`parse_line` dispatches
on it, :func:`help_text` prints it (``help``), and :func:`markdown_table` renders it for the docs
(``python3 -m modrob_motion.terminal_parser`` prints it; a test keeps docs/bulbs_and_slides.md in
step). Every error is a :class:`ParseError` whose message is one line, fit to show the user.
"""
import collections
import math
import sys

from modrob_motion.errors import ParseError


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


def _number(token):
    try:
        value = float(token)
    except ValueError:
        raise ParseError("'%s' is neither a number nor a command (type help)" % token)
    if not math.isfinite(value):
        raise ParseError("'%s' is not a finite number" % token)
    return value


def _no_arguments(cls):
    def parse(word, args):
        if args:
            raise ParseError("'%s' takes no arguments" % word)
        return cls()
    return parse


def _radians(word, args):
    return JointTarget(_number(t) for t in args)


def _degrees(word, args):
    if not args:
        raise ParseError("%s needs joint angles in degrees, e.g. deg 10 45 -20" % word)
    return JointTarget(math.radians(_number(t)) for t in args)


def _robot(word, args):
    rest = word[1:] + "".join(args)
    if not rest.isdigit():
        raise ParseError("'%s': a robot is chosen by its number, for example #1"
                         % " ".join((word,) + tuple(args)))
    return SelectRobot(int(rest))


def _xyz(word, args):
    if len(args) != 3:
        raise ParseError("xyz needs three numbers (metres, world frame), e.g. xyz 0.4 0.1 1.3")
    return CartesianTarget(_number(t) for t in args)


def _gripper(word, args):
    if args:
        raise ParseError("'%s' takes no arguments" % word)
    return GripperCommand(word)


#: One row per command: the words that start it (the first is its name; ``None`` = a line of
#: numbers, ``"#"`` = a prefix), its arguments as shown to users, what it does, and its parser
#: ``parse(word, args) -> Command``.
CommandSpec = collections.namedtuple("CommandSpec", "words args does parse")
COMMANDS = (
    CommandSpec((None,), "0.1 0.5 -0.3 ...", "joint angles in rad, one per arm joint (commas allowed)",
                _radians),
    CommandSpec(("deg", "degrees"), "10 45 -20 ...", "joint angles in degrees", _degrees),
    CommandSpec(("#",), "<N>", "control robot N from now on, e.g. #1 (its URDF: /modrobN/robot_description)",
                _robot),
    CommandSpec(("home",), "", "every arm joint to 0 (or to the nearer limit when 0 is outside them)",
                _no_arguments(Home)),
    CommandSpec(("open",), "", "open the gripper (the finger limit farther from the other finger)", _gripper),
    CommandSpec(("close",), "", "close the gripper", _gripper),
    CommandSpec(("xyz",), "<x> <y> <z>", "the end effector (grasp centre) to a point in the world frame (m), "
                "by KDL IK", _xyz),
    CommandSpec(("state", "status"), "", "show commanded and measured joint angles", _no_arguments(State)),
    CommandSpec(("help", "h", "?"), "", "this table", _no_arguments(Help)),
    CommandSpec(("quit", "exit", "q"), "", "leave the terminal (Ctrl-D too)", _no_arguments(Quit)),
)
_BY_WORD = {w: spec for spec in COMMANDS for w in spec.words if w not in (None, "#")}


def usage(spec):
    """How a user types ``spec``: ``xyz <x> <y> <z>``, ``#<id>``, ``state``."""
    if spec.words == (None,):
        return spec.args
    if spec.words == ("#",):
        return "#" + spec.args
    return spec.words[0] + (" " + spec.args if spec.args else "")


def aliases(spec):
    """The other words that start ``spec`` (``status`` for ``state``)."""
    return [w for w in spec.words[1:] if w]


def help_text():
    width = max(len(usage(c)) for c in COMMANDS)
    lines = []
    for c in COMMANDS:
        also = " (also: %s)" % ", ".join(aliases(c)) if aliases(c) else ""
        lines.append("  %-*s  %s%s" % (width, usage(c), c.does, also))
    return "\n".join(lines)


def markdown_table():
    rows = ["| line | does |", "|---|---|"]
    for c in COMMANDS:
        also = " (also %s)" % ", ".join("`%s`" % w for w in aliases(c)) if aliases(c) else ""
        rows.append("| `%s`%s | %s |" % (usage(c), also, c.does))
    return "\n".join(rows)


def parse_line(line):
    """Returns a Command, or None for a blank line. Raises ParseError."""
    if line is None:
        return Quit()
    text = line.strip()
    if not text:
        return None
    tokens = text.replace(",", " ").split()
    word, args = tokens[0].lower(), tokens[1:]
    if word.startswith("#"):
        return _robot(word, args)
    spec = _BY_WORD.get(word)
    if spec is None:
        return _radians(None, tokens)
    return spec.parse(word, args)


if __name__ == "__main__":
    sys.stdout.write(markdown_table() + "\n")
