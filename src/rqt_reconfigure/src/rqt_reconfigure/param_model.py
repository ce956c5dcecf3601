"""The pure core of the reconfigure GUI (no rospy, no Qt): parameters and groups from a
dynamic_reconfigure description, value <-> slider mapping, parsing what the user types, and the
tree of server names the GUI shows.

The description is the group tree ``dynamic_reconfigure.encoding.decode_description`` returns:
``{'name', 'type', 'state', 'parameters': [{'name', 'type', 'min', 'max', 'default',
'description', 'edit_method', 'level'}], 'groups': {name: group, ...}}``."""
import ast
import math

from rqt_reconfigure.errors import ReconfigureError

TYPES = ("int", "double", "bool", "str")
SLIDER_TICKS = 10000          # a double slider has this many steps between min and max


class EnumChoice(object):
    def __init__(self, name, value, description=""):
        self.name = name
        self.value = value
        self.description = description

    def __repr__(self):
        return "EnumChoice(%r, %r)" % (self.name, self.value)


class ParamSpec(object):
    """One parameter as the server describes it."""

    def __init__(self, name, kind, minimum=None, maximum=None, default=None, description="",
                 enum=None, level=0):
        if kind not in TYPES:
            raise ReconfigureError("parameter '%s' has type '%s'; dynamic_reconfigure knows %s"
                                   % (name, kind, ", ".join(TYPES)))
        self.name = name
        self.kind = kind
        self.minimum = minimum
        self.maximum = maximum
        self.default = default
        self.description = description
        self.enum = enum or []
        self.level = level

    @property
    def has_range(self):
        """True when a slider makes sense: a number with finite, ordered bounds."""
        if self.kind not in ("int", "double") or self.minimum is None or self.maximum is None:
            return False
        return (math.isfinite(float(self.minimum)) and math.isfinite(float(self.maximum))
                and self.maximum > self.minimum)

    def to_ticks(self, value):
        """Slider position for ``value`` (clamped into the range)."""
        if self.kind == "int":
            return int(min(max(value, self.minimum), self.maximum))
        frac = (float(value) - self.minimum) / (self.maximum - self.minimum)
        return int(round(min(max(frac, 0.0), 1.0) * SLIDER_TICKS))

    def tick_range(self):
        if self.kind == "int":
            return int(self.minimum), int(self.maximum)
        return 0, SLIDER_TICKS

    def from_ticks(self, ticks):
        """The value at slider position ``ticks``; doubles are rounded to the slider's resolution
        so that a slider move gives a readable number (200.0, not 199.99999998)."""
        if self.kind == "int":
            return int(ticks)
        step = (self.maximum - self.minimum) / SLIDER_TICKS
        value = self.minimum + ticks * step
        digits = max(0, -int(math.floor(math.log10(step)))) if step > 0 else 6
        return round(value, digits)

    def parse(self, text):
        """The value the user typed, converted and checked; ReconfigureError says what is wrong."""
        text = text.strip()
        try:
            if self.kind == "double":
                value = float(text)
                if not math.isfinite(value):
                    raise ValueError(text)
            elif self.kind == "int":
                value = int(text)
            elif self.kind == "bool":
                if text.lower() not in ("true", "false", "1", "0"):
                    raise ValueError(text)
                value = text.lower() in ("true", "1")
            else:
                value = text
        except ValueError:
            raise ReconfigureError("'%s' is not a finite %s for parameter '%s'"
                                   % (text, self.kind, self.name))
        if self.kind in ("int", "double") and self.minimum is not None and self.maximum is not None:
            if not self.minimum <= value <= self.maximum:
                raise ReconfigureError("%s = %s is outside [%s, %s] (the server's range)"
                                       % (self.name, text, format_value(self.minimum),
                                          format_value(self.maximum)))
        return value


class GroupSpec(object):
    def __init__(self, name, params, groups, kind=""):
        self.name = name
        self.params = params
        self.groups = groups
        self.kind = kind

    def all_params(self):
        out = list(self.params)
        for g in self.groups:
            out.extend(g.all_params())
        return out


def parse_edit_method(text, param_name):
    """Enum choices from a parameter's ``edit_method`` string ('' when there is none)."""
    if not text:
        return []
    try:
        method = ast.literal_eval(text)
    except (ValueError, SyntaxError):
        raise ReconfigureError("parameter '%s' has an edit_method that is not a Python literal: %.60s"
                               % (param_name, text))
    if not isinstance(method, dict):
        return []
    choices = []
    for item in method.get("enum", []):
        try:
            choices.append(EnumChoice(item["name"], item["value"], item.get("description", "")))
        except (KeyError, TypeError):
            raise ReconfigureError("parameter '%s' has an enum entry without name/value: %r"
                                   % (param_name, item))
    return choices


def param_from_dict(d):
    try:
        name = d["name"]
        kind = d["type"]
    except (KeyError, TypeError):
        raise ReconfigureError("a parameter description lacks 'name' or 'type': %r" % (d,))
    return ParamSpec(name, kind, d.get("min"), d.get("max"), d.get("default"), d.get("description", ""),
                     parse_edit_method(d.get("edit_method", ""), name), d.get("level", 0))


def group_from_dict(d):
    """A GroupSpec tree from decode_description's dict."""
    if not isinstance(d, dict) or "parameters" not in d:
        raise ReconfigureError("the server's description is not a dynamic_reconfigure group tree")
    params = [param_from_dict(p) for p in d.get("parameters", [])]
    children = d.get("groups") or {}
    groups = [group_from_dict(g) for g in (children.values() if isinstance(children, dict) else children)]
    return GroupSpec(d.get("name", "Default"), params, groups, d.get("type", ""))


def format_value(value):
    """A number as the GUI shows it: ints plain, doubles with up to 6 significant digits."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "%.6g" % (value + 0.0)      # + 0.0 turns -0.0 into 0.0
    return str(value)


def server_tree(names):
    """Nested dict of path components for the servers' names, e.g. ['/a/b/pid'] ->
    {'a': {'b': {'pid': {}}}}; a component that is a server and also has servers below is both."""
    tree = {}
    for name in sorted(names):
        node = tree
        for part in [p for p in name.split("/") if p]:
            node = node.setdefault(part, {})
    return tree


def matches(name, pattern):
    """Filter box semantics: every blank-separated word of ``pattern`` occurs in ``name``
    (case-insensitive), as rqt_reconfigure's filter key does with one word."""
    lowered = name.lower()
    return all(word in lowered for word in pattern.lower().split())
