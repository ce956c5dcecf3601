"""The names every ``${...}`` expression sees (xacro 1.14's global symbols).

- directly: ``list dict map len str float int True False min max round`` and every public name of
  ``math`` (``pi``, ``sin``, ...); ``sorted``, ``range`` and ``load_yaml``, ``abs_filename``,
  ``dotify`` too, with a warning to use their namespaced names;
- ``python.*``: those builtins plus ``abs all any complex divmod enumerate filter frozenset hash
  isinstance issubclass ord repr reversed slice set sorted range sum tuple type zip``;
- ``math.*``: the math module;
- ``xacro.*``: ``load_yaml``, ``abs_filename``, ``dotify``, ``arg``, ``tokenize``, ``message``,
  ``warning``, ``error``, ``fatal``, ``print_location``.
"""
import builtins
import math
import re

from .errors import XacroException, error, message, warning
from .scope import NameSpace
from .yaml_data import DottedDict

_DIRECT_BUILTINS = ("list", "dict", "map", "len", "str", "float", "int", "True", "False",
                    "min", "max", "round")
_PYTHON_BUILTINS = _DIRECT_BUILTINS + (
    "abs", "all", "any", "complex", "divmod", "enumerate", "filter", "frozenset", "hash",
    "isinstance", "issubclass", "ord", "repr", "reversed", "slice", "set", "sorted", "range",
    "sum", "tuple", "type", "zip")


def tokenize(text, sep=",; ", skip_empty=True):
    """Split text at any of the characters in sep (empty items dropped unless skip_empty=False)."""
    items = re.split("[%s]" % re.escape(sep), text)
    return [i for i in items if i] if skip_empty else items


def _deprecated(func, name, ns):
    def call(*args, **kwargs):
        warning("Using %s() directly is deprecated. Use %s.%s() instead." % (name, ns, name))
        return func(*args, **kwargs)
    return call


def global_symbols(processor):
    """The root symbol table of one xacro run (``processor`` answers arg, load_yaml, location)."""
    symbols = {}
    python_ns = NameSpace()
    for name in _PYTHON_BUILTINS:
        value = {"True": True, "False": False}.get(name) if name in ("True", "False") \
            else getattr(builtins, name)
        dict.__setitem__(python_ns, name, value)
        if name in _DIRECT_BUILTINS:
            symbols[name] = value
    for name in ("sorted", "range"):
        symbols[name] = _deprecated(python_ns[name], name, "python")

    math_ns = NameSpace()
    for name, value in vars(math).items():
        if not name.startswith("_"):
            dict.__setitem__(math_ns, name, value)
            symbols[name] = value

    def reporter(report, location_by_default):
        def call(*args, **kwargs):
            show_location = kwargs.pop("print_location", location_by_default)
            kwargs.pop("file", None)
            report(*args, **kwargs)
            if show_location:
                processor.print_location()
            return ""   # so that ${xacro.warning(...)} leaves no text behind
        return call

    def fatal(*args):
        raise XacroException(" ".join(str(a) for a in args))

    def arg(name):
        try:
            return processor.args[name]
        except KeyError:
            raise XacroException("xacro.arg('%s'): no such argument (give %s:=<value> or declare "
                                 "<xacro:arg name=\"%s\" default=\"...\"/>)" % (name, name, name))

    xacro_ns = NameSpace()
    for name, value in (("load_yaml", processor.load_yaml), ("abs_filename", processor.abs_filename),
                        ("dotify", DottedDict)):
        dict.__setitem__(xacro_ns, name, value)
        symbols[name] = _deprecated(value, name, "xacro")
    for name, value in (("arg", arg), ("tokenize", tokenize), ("fatal", fatal),
                        ("message", reporter(message, False)), ("warning", reporter(warning, True)),
                        ("error", reporter(error, True)),
                        ("print_location", reporter(lambda: None, True))):
        dict.__setitem__(xacro_ns, name, value)

    symbols.update(python=python_ns, math=math_ns, xacro=xacro_ns)
    return symbols
