"""Property and macro tables: one per scope, each looking up what it lacks in the enclosing one.

A property given as text is kept as text and evaluated when first read (xacro's ``lazy_eval``),
in the scope that defined it; the result then replaces the text. Values that read as numbers or
booleans are converted when stored, as xacro does: ``"0.5"`` is the float 0.5, ``"true"`` is True,
``"'0.5'"`` (quoted) stays the string ``0.5``, and text with an underscore stays text.
"""
from .errors import XacroException, warning


def literal(value):
    """The number, boolean or unquoted string a property value written as text stands for."""
    if not isinstance(value, str):
        return value
    if len(value) >= 2 and value[0] == "'" and value[-1] == "'":
        return value[1:-1]
    if "_" in value:   # Python reads 1_000 as a number; xacro keeps it as text
        return value
    for convert in (int, float):
        try:
            return convert(value)
        except ValueError:
            pass
    return {"true": True, "True": True, "false": False, "False": False}.get(value, value)


class Table(dict):
    """Names defined in one scope; the enclosing table (or the plain dict at the root) answers
    for the others. ``evaluate(text, table)`` turns a lazily stored text into its value."""

    def __init__(self, parent=None, evaluate=None, log=None):
        super().__init__()
        self._parent = {} if parent is None else parent
        self._root = getattr(self._parent, "_root", self._parent)
        self._evaluate = evaluate or getattr(self._parent, "_evaluate", None)
        self._log = log or getattr(self._parent, "_log", None)   # f("set"/"use", table, key, value)
        self._unevaluated = set()
        self._resolving = []

    @property
    def parent(self):
        return self._parent

    def _resolve(self, key):
        if key in self._unevaluated:
            if key in self._resolving:
                raise XacroException("circular variable definition: %s\nConsider disabling lazy "
                                     "evaluation via lazy_eval=\"false\""
                                     % " -> ".join(self._resolving + [key]))
            self._resolving.append(key)
            try:
                value = literal(self._evaluate(dict.__getitem__(self, key), self))
            finally:
                self._resolving.remove(key)
            dict.__setitem__(self, key, value)
            self._unevaluated.discard(key)
        value = dict.__getitem__(self, key)
        if self._log:
            self._log("use", self, key, value)
        return value

    def __getitem__(self, key):
        if dict.__contains__(self, key):
            return self._resolve(key)
        return self._parent[key]

    def __contains__(self, key):
        return dict.__contains__(self, key) or key in self._parent

    def get(self, key, default=None):
        return self[key] if key in self else default

    def set(self, key, value, lazy):
        """Store a value; text that is not a number or boolean waits for its first read when lazy."""
        if key in self._root:
            warning("redefining global symbol: %s" % key)
        value = literal(value)
        dict.__setitem__(self, key, value)
        if lazy and isinstance(value, str):
            self._unevaluated.add(key)
        else:
            self._unevaluated.discard(key)
        if self._log:
            self._log("set", self, key, value)

    def __setitem__(self, key, value):
        self.set(key, value, lazy=True)

    def __delitem__(self, key):
        """Forget a name in this scope and every enclosing one (global symbols stay)."""
        table = self
        while table is not self._root:
            dict.pop(table, key, None)
            table._unevaluated.discard(key)
            table = table._parent
        if key in self._root:
            warning("Cannot remove global symbol: %s" % key)

    def top(self):
        """The document's own scope: the outermost table below the global symbols."""
        table = self
        while table._parent is not self._root:
            table = table._parent
        return table

    def depth(self):
        n, table = 0, self
        while table is not self._root:
            n, table = n + 1, table._parent
        return n


_INTERNAL = ("_parent", "_root", "_evaluate", "_log", "_unevaluated", "_resolving")


class NameSpace(Table):
    """The table of an ``<xacro:include ns="...">``: its names are read as ``ns.name``."""

    def __getattr__(self, name):
        if name.startswith("__") or name in _INTERNAL:   # copy, pickle, or __init__ not done yet
            raise AttributeError(name)
        try:
            return self[name]
        except KeyError:
            raise NameError("name '%s' is not defined" % name) from None
