"""``xacro.load_yaml``: YAML files as property values, with dotted access and unit tags.

The loaded dictionaries read as ``d.key.sub`` as well as ``d['key']['sub']``, also inside lists and
while iterating. Scalars tagged with a unit are converted to SI on loading: ``!radians``,
``!degrees``, ``!meters``, ``!millimeters``, ``!foot``, ``!inches``; the tagged text may be an
expression (``!degrees 90/2``, ``!radians pi/4``).
"""
import math

import yaml

from .errors import XacroException
from .expressions import safe_eval

UNITS = {
    "!radians": 1.0,
    "!degrees": math.pi / 180.0,
    "!meters": 1.0,
    "!millimeters": 0.001,
    "!foot": 0.3048,
    "!inches": 0.0254,
}


def wrap(value):
    if isinstance(value, dict) and not isinstance(value, DottedDict):
        return DottedDict(value)
    if isinstance(value, list) and not isinstance(value, DottedList):
        return DottedList(value)
    return value


class DottedList(list):
    """A YAML list whose dictionaries give dotted access when read or iterated."""

    def __getitem__(self, index):
        return wrap(super().__getitem__(index))

    def __iter__(self):
        for item in super().__iter__():
            yield wrap(item)


class DottedDict(dict):
    """A dictionary readable as ``d.key``; a missing key is an AttributeError (so hasattr works)."""

    def __getattr__(self, key):
        try:
            return wrap(dict.__getitem__(self, key))
        except KeyError:
            raise AttributeError("The yaml dictionary has no key '%s'" % key) from None

    __getitem__ = __getattr__


def _loader_class(symbols):
    """A safe YAML loader that knows the unit tags; their expressions see ``symbols``."""

    class UnitLoader(yaml.SafeLoader):
        pass

    def constructor(factor):
        def construct(loader, node):
            text = loader.construct_scalar(node)
            try:
                return float(safe_eval(str(text), dict(symbols))) * factor
            except Exception as e:
                raise XacroException("invalid expression in %s %s: %s" % (node.tag, text, e))
        return construct

    for tag, factor in UNITS.items():
        UnitLoader.add_constructor(tag, constructor(factor))
    return UnitLoader


def load_yaml(path, symbols):
    """The YAML file's content with dotted access; ``symbols`` are the global symbols."""
    try:
        with open(path) as f:
            return wrap(yaml.load(f, Loader=_loader_class(symbols)))
    except OSError as e:
        raise XacroException("cannot read the YAML file %s: %s" % (path, e.strerror), exc=None)
    except yaml.YAMLError as e:
        raise XacroException("the YAML file %s is not valid YAML:" % path, exc=e)
