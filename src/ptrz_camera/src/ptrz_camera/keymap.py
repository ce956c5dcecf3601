"""The keyboard teleop of seed 002 (section 3.2, appendix B.4) as a pure state machine.

One table, :data:`KEYS`, drives both the key bindings and the help text. The seed's behaviour:
q/w roll -/+ step, a/s pan -/+ step, z/x tilt -/+ step, e/d multiply/divide the step by 1.1
(from 0.1), h home (all joints 0, step 0.1), Ctrl-C quits; after every key the positions
(roll, pan, tilt) and the step are printed, and the help is printed again after 6 presses.
Added: +/- zoom in/out (the field of view divided/multiplied by ZOOM_STEP), h also restores the
starting field of view."""
from collections import namedtuple

DIFF = 0.1          # the seed's initial step, rad
STEP = 1.1          # the seed's step multiplier
ZOOM_STEP = 1.25    # focal length x1.25 per press
HELP_EVERY = 6      # the seed reprints the help after 6 presses
CTRL_C = "\x03"

Key = namedtuple("Key", "key action arg help")

#: (key, action, argument, help line). Joint actions move the target by +-step.
KEYS = (
    Key("q", "joint", ("roll", -1), "roll clockwise"),
    Key("w", "joint", ("roll", +1), "roll anticlockwise"),
    Key("a", "joint", ("pan", -1), "pan clockwise"),
    Key("s", "joint", ("pan", +1), "pan anticlockwise"),
    Key("z", "joint", ("tilt", -1), "tilt up"),
    Key("x", "joint", ("tilt", +1), "tilt down"),
    Key("e", "step", STEP, "increase speed (step x %g)" % STEP),
    Key("d", "step", 1.0 / STEP, "decrease speed (step / %g)" % STEP),
    Key("+", "zoom", 1.0 / ZOOM_STEP, "zoom in (field of view / %g)" % ZOOM_STEP),
    Key("-", "zoom", ZOOM_STEP, "zoom out (field of view x %g)" % ZOOM_STEP),
    Key("h", "home", None, "starting position"),
)
BINDINGS = {k.key: k for k in KEYS}
JOINTS = ("roll", "pan", "tilt")     # the seed's target_pos1, 2, 3
STRIPES = "-" * 29


def help_text(ns="/ptrz"):
    """The seed's instruction text, built from :data:`KEYS` (pairs on one line as in figure 3.2)."""
    lines = ["Control Your ptrz camera (%s)" % ns, "---------------------------", "Moving around:"]
    i = 0
    while i < len(KEYS):
        k = KEYS[i]
        nxt = KEYS[i + 1] if i + 1 < len(KEYS) else None
        if nxt is not None and nxt.action == k.action and k.action != "home":
            lines.append("   %s  %s   %s / %s" % (k.key, nxt.key, k.help, nxt.help))
            i += 2
        else:
            lines.append("   %s      %s" % (k.key, k.help))
            i += 1
    lines.append("CTRL-C to quit")
    return "\n".join(lines)


class TeleopState(object):
    """Targets, step and zoom of the teleop; :meth:`press` returns the lines to print (or None
    for keys that are not bound) and sets :attr:`quit` on Ctrl-C."""

    def __init__(self, fov=1.3962634, fov_range=(0.0, float("inf")), ns="/ptrz"):
        self.ns = ns
        self.home_fov = fov
        self.fov_range = fov_range
        self.quit = False
        self.zoom_changed = False
        self.home()

    def home(self):
        self.targets = dict(roll=0.0, pan=0.0, tilt=0.0)
        self.diff = DIFF
        self.status = 0
        self.fov = self.home_fov

    def status_lines(self):
        return [STRIPES, "roll %.4f  pan %.4f  tilt %.4f" % tuple(self.targets[j] for j in JOINTS),
                "step %.4f  fov %.4f rad" % (self.diff, self.fov)]

    def press(self, key):
        self.zoom_changed = False
        if key == CTRL_C:
            self.quit = True
            return []
        binding = BINDINGS.get(key)
        if binding is None:
            return None
        out = []
        if binding.action == "joint":
            joint, sign = binding.arg
            self.targets[joint] += sign * self.diff
        elif binding.action == "step":
            self.diff *= binding.arg
        elif binding.action == "zoom":
            fov = self.fov * binding.arg
            lo, hi = self.fov_range
            if lo <= fov <= hi:
                self.fov = fov
                self.zoom_changed = True
            else:
                out.append("zoom limit: field of view %.4f rad is outside the camera's range [%.4f, %.4f]"
                           % (fov, lo, hi))
        elif binding.action == "home":
            self.zoom_changed = self.fov != self.home_fov
            self.home()
            return self.status_lines()
        self.status += 1
        out.extend(self.status_lines())
        if self.status == HELP_EVERY:
            out.append(help_text(self.ns))
            self.status = 0
        return out

    def commands(self):
        """(roll, pan, tilt) targets, the seed's publishing order."""
        return tuple(self.targets[j] for j in JOINTS)
