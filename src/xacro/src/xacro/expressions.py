"""Text with ``${python expression}`` and ``$(substitution arg)`` parts, evaluated as xacro does.

- ``${...}`` is a Python expression over the properties in scope and the global symbols (no
  Python builtins beyond those, no name starting with ``__``);
- ``$(...)`` is a roslaunch substitution (``find``, ``arg``, ``env``, ``optenv``, ``eval``,
  ``dirname``) or ``$(cwd)``;
- ``$${`` and ``$$(`` stand for a literal ``${`` and ``$(``.

A text that is one single part evaluates to that part's value (a number stays a number); several
parts are joined as text.
"""
import os
import re

from .errors import XacroException

# One token at the start of the remaining text, tried in this order.
_TOKENS = [
    ("escaped", re.compile(r"\$\$+[{(]")),   # $${ or $$( ... : one '$' less, nothing evaluated
    ("expr", re.compile(r"\$\{[^}]*\}")),
    ("subst", re.compile(r"\$\([^)]*\)")),
    ("text", re.compile(r"[^$]+|\$[^{($]+|\$$")),
]


def tokens(text):
    """(kind, token) pairs of a text; an unclosed ``${`` or ``$(`` raises."""
    pos = 0
    while pos < len(text):
        for kind, pattern in _TOKENS:
            m = pattern.match(text, pos)
            if m:
                yield kind, m.group(0)
                pos = m.end()
                break
        else:
            raise XacroException("invalid expression: %s (a '${' or '$(' without its closing "
                                 "brace; write '$${' for a literal '${')" % text[pos:])


def _all_names(code):
    names = set(code.co_names)
    for const in code.co_consts:
        if hasattr(const, "co_names"):
            names |= _all_names(const)
    return names


def safe_eval(expr, symbols):
    """Evaluate a Python expression with only the names in ``symbols`` (a dict) available."""
    code = compile(expr.strip(), "<expression>", "eval")
    hidden = sorted(n for n in _all_names(code) if n.startswith("__"))
    if hidden:
        raise XacroException("Use of invalid name(s): %s" % ", ".join(hidden))
    dict.__setitem__(symbols, "__builtins__", {})   # stored in the dict itself: no Python builtins
    return eval(code, symbols)


class Evaluator:
    """Evaluates texts for one xacro run: ``args`` are the xacro arguments (``name:=value`` and
    ``<xacro:arg>``), ``current_file()`` names the file being read (for ``$(dirname)``)."""

    def __init__(self, args, current_file):
        self.args = args
        self.current_file = current_file

    def __call__(self, text, symbols):
        return self.text(text, symbols)

    def text(self, text, symbols):
        parts = []
        for kind, token in tokens(text):
            if kind == "text":
                parts.append(token)
            elif kind == "escaped":
                parts.append(token[1:])
            elif kind == "expr":
                parts.append(self._expression(token[2:-1], symbols))
            else:
                parts.append(self.substitution(str(self.text(token[2:-1], symbols))))
        if len(parts) == 1:
            return parts[0]
        return "".join(str(p) for p in parts)

    def _expression(self, source, symbols):
        try:
            return safe_eval(str(self.text(source, symbols)), symbols)
        except XacroException as e:
            if e.suffix is None:
                e.suffix = os.linesep + "when evaluating expression '%s'" % source
            raise
        except Exception as e:
            raise XacroException(exc=e, suffix=os.linesep + "when evaluating expression '%s'" % source)

    def substitution(self, inner):
        """The value of ``$(inner)``."""
        if inner.strip() == "cwd":
            return os.getcwd()
        try:
            from roslaunch.substitution_args import ArgException, resolve_args
            from rospkg.common import ResourceNotFound
        except ImportError as e:
            raise XacroException("substitution args not supported (roslaunch is not importable; "
                                 "source the ROS environment):", exc=e)
        context = {"arg": self.args}
        here = self.current_file()
        if here:
            context["filename"] = here   # for $(dirname)
        try:
            return resolve_args("$(%s)" % inner, context=context, resolve_anon=False)
        except ArgException as e:
            raise XacroException("Undefined substitution argument", exc=e,
                                 suffix="(give it on the command line as %s:=<value> or declare "
                                        "<xacro:arg name=\"%s\" default=\"...\"/>)" % (e, e))
        except ResourceNotFound as e:
            raise XacroException("resource not found:", exc=e,
                                 suffix="(is the package on ROS_PACKAGE_PATH?)")
        except Exception as e:   # roslaunch's SubstitutionException and friends
            raise XacroException("$(%s):" % inner, exc=e)
