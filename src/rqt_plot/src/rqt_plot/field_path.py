"""rqt_plot's series names, pure (no rospy): ``/topic/field/sub[index]``, and
``/topic/field/a:b`` for two fields of one topic, as rqt_plot and rxplot accept them.

Which leading part is the topic is decided against the topics the master knows (the longest
one that is a prefix wins); the rest is a field path checked against the message class
(genpy's ``__slots__``/``_slot_types``), so a typo is reported with the fields that exist."""
import math
import re

from rqt_plot.errors import PlotError

NUMERIC = {"bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
           "float32", "float64"}
TIME = {"time", "duration"}
_PART = re.compile(r"^([A-Za-z][A-Za-z0-9_]*)(?:\[(\d+)\])?$")


def expand(spec):
    """'/a/b/x:y' -> ['/a/b/x', '/a/b/y']; '/a/b/x' -> ['/a/b/x']."""
    if ":" not in spec:
        return [spec]
    head, _, tail = spec.rpartition("/")
    if not head:
        raise PlotError("'%s' has ':' but no topic before it; write /topic/field1:field2" % spec)
    return ["%s/%s" % (head, f) for f in tail.split(":") if f]


def split_topic(spec, topics):
    """(topic, field text) for ``spec``, the topic being the longest known topic that prefixes it."""
    if not spec.startswith("/"):
        spec = "/" + spec
    spec = spec.rstrip("/")
    best = None
    for t in topics:
        if (spec == t or spec.startswith(t.rstrip("/") + "/")) and (best is None or len(t) > len(best)):
            best = t
    if best is None:
        return None
    return best, spec[len(best):].strip("/")


def parse_fields(text):
    """'position[2]' -> [('position', 2)]; 'pose/position/x' -> [('pose', None), ...]."""
    if not text:
        return []
    out = []
    for part in text.split("/"):
        m = _PART.match(part)
        if not m:
            raise PlotError("'%s' is not a field name (letters, digits, _; an index as [3])" % part)
        out.append((m.group(1), int(m.group(2)) if m.group(2) is not None else None))
    return out


def check_path(msg_class, fields, lookup, topic=""):
    """Check ``fields`` against ``msg_class``; ``lookup(type_name)`` returns a nested message class.
    Raises PlotError naming the field and listing what exists; returns the leaf's type name."""
    cls = msg_class
    where = topic
    if not fields:
        raise PlotError("%s: give a numeric field to plot, e.g. %s/%s (fields of %s: %s)"
                        % (topic, topic, _first_numeric(cls), cls._type, ", ".join(cls.__slots__)))
    for i, (name, index) in enumerate(fields):
        if name not in cls.__slots__:
            raise PlotError("%s: '%s' is not a field of %s (its fields: %s)"
                            % (where or "the message", name, cls._type, ", ".join(cls.__slots__)))
        kind = cls._slot_types[cls.__slots__.index(name)]
        where = "%s/%s" % (where, name)
        is_array = kind.endswith("]")
        base = kind[:kind.index("[")] if is_array else kind
        if is_array and index is None:
            raise PlotError("%s is an array (%s): give an index, e.g. %s[0]" % (where, kind, name))
        if not is_array and index is not None:
            raise PlotError("%s is not an array (%s): drop the [%d]" % (where, kind, index))
        last = i == len(fields) - 1
        if base in NUMERIC or base in TIME:
            if not last:
                raise PlotError("%s is a %s and has no field '%s'" % (where, base, fields[i + 1][0]))
            return base
        if base == "string":
            raise PlotError("%s is a string; only numbers (and bools, times) can be plotted" % where)
        if last:
            sub = lookup(base)
            raise PlotError("%s is a %s message, not a number; plot one of its fields, e.g. %s/%s"
                            % (where, base, where, _first_numeric(sub) if sub else "x"))
        cls = lookup(base)
        if cls is None:
            raise PlotError("%s: message type %s is unknown here" % (where, base))
    return None


def _first_numeric(cls):
    for name, kind in zip(cls.__slots__, cls._slot_types):
        if kind in NUMERIC:
            return name
    return cls.__slots__[0] if cls.__slots__ else "field"


def extract(msg, fields):
    """The float value at ``fields`` in ``msg``; None when an index is beyond this message's array
    (arrays may be shorter in some messages) or the value is not finite."""
    value = msg
    for name, index in fields:
        value = getattr(value, name)
        if index is not None:
            if index >= len(value):
                return None
            value = value[index]
    if hasattr(value, "to_sec"):
        value = value.to_sec()
    value = float(value)
    return value if math.isfinite(value) else None
