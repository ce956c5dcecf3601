"""Keyboard teleoperation of the Katana in the spirit of katana_teleop_key (pure core: the key
table and what a key does; ``teleop_node`` reads the keyboard and talks to the actions).

One table, ``KEYS``, gives the bindings and the help text.
"""
import math

from katana_sim import kinematics as kin
from katana_sim.gripper import CLOSED_ANGLE, OPEN_ANGLE

#: (keys, action, help) - the only key table: the help text and the dispatch come from it
KEYS = (
    ("w", "up", "selected joint + increment"),
    ("s", "down", "selected joint - increment"),
    ("d", "next", "select the next joint"),
    ("a", "previous", "select the previous joint"),
    ("01234", "select", "select joint 0..4 by number"),
    ("+", "more", "increment + step"),
    ("-#", "less", "increment - step"),
    ("o", "open", "open the gripper"),
    ("c", "close", "close the gripper"),
    ("r", "home", "back to the home pose"),
    ("i", "info", "this help and the joint positions"),
    ("q", "quit", "quit (Ctrl-C too)"),
)


class Command(object):
    """What the ROS layer should do: kind in (move, grip, info, quit, none)."""
    __slots__ = ("kind", "positions", "gripper", "text")

    def __init__(self, kind, positions=None, gripper=None, text=""):
        self.kind, self.positions, self.gripper, self.text = kind, positions, gripper, text


def help_text(state=None):
    lines = ["Katana keyboard teleop (katana_teleop_key style):"]
    for keys, _, text in KEYS:
        lines.append("  %-6s %s" % (" ".join(keys), text))
    if state is not None:
        lines.append("selected joint %d (%s), increment %.3f rad (step %.3f)"
                     % (state.joint, kin.JOINTS[state.joint], state.increment, state.step))
    return "\n".join(lines)


class TeleopState(object):
    def __init__(self, increment=math.radians(5.0), step=math.radians(1.0)):
        self.joint = 0
        self.increment = increment
        self.step = step
        self._action = {}
        for keys, action, _ in KEYS:
            for k in keys:
                self._action[k] = action

    def handle(self, key, current):
        """``key`` one character, ``current`` the five arm joint positions; returns a Command."""
        action = self._action.get(key.lower() if key not in "+-#" else key)
        if key == "\x03":
            action = "quit"
        if action is None:
            return Command("none", text="key %r is not bound (i: help)" % key)
        if action in ("up", "down"):
            q = list(current)
            sign = 1.0 if action == "up" else -1.0
            j = self.joint
            want = q[j] + sign * self.increment
            q[j] = min(max(want, kin.LOWER[j]), kin.UPPER[j])
            text = "%s -> %.3f rad" % (kin.JOINTS[j], q[j])
            if q[j] != want:
                text += " (joint limit)"
            return Command("move", positions=q, text=text)
        if action in ("next", "previous"):
            self.joint = (self.joint + (1 if action == "next" else -1)) % len(kin.JOINTS)
            return Command("none", text="selected joint %d: %s" % (self.joint, kin.JOINTS[self.joint]))
        if action == "select":
            self.joint = int(key)
            return Command("none", text="selected joint %d: %s" % (self.joint, kin.JOINTS[self.joint]))
        if action in ("more", "less"):
            self.increment = max(0.0, self.increment + (self.step if action == "more" else -self.step))
            return Command("none", text="increment %.3f rad" % self.increment)
        if action in ("open", "close"):
            return Command("grip", gripper=OPEN_ANGLE if action == "open" else CLOSED_ANGLE,
                           text="gripper %s" % action)
        if action == "home":
            return Command("move", positions=list(kin.HOME), text="home pose")
        if action == "info":
            return Command("info", text=help_text(self) + "\n" + "\n".join(
                "  %d %s: %.3f" % (i, n, q) for i, (n, q) in enumerate(zip(kin.JOINTS, current))))
        return Command("quit", text="bye")
