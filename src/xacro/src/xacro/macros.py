"""Macro definitions and their ``params`` attribute.

A params attribute lists names separated by blanks; each is

    name            required
    name:=default   (or name=default) with a default; the default is ${...}, $(...), or a run of
                    characters without blanks in which '...' or "..." may hold blanks
    name:=^         taken from the caller's property of the same name (required there)
    name:=^|default taken from the caller's property, else the default
    *name           one element block (inserted as the element)
    **name          one element block (inserted as the element's content)

``name:=`` with nothing after it declares no default: the parameter stays required.
"""
from .errors import XacroException


class Macro:
    """A macro: its <xacro:macro> element, parameter names in order, and defaults by name as
    (forward_name or None, default_text or None)."""

    def __init__(self, name):
        self.name = name
        self.body = None
        self.params = []
        self.defaults = {}
        self.defined_in = []   # the file stack of each definition, the last one current


def _closing(text, start, opener, closer):
    """End index of a ${...}/$(...) default starting at start: the first closer that is followed
    by a blank or the end, else None."""
    pos = start + 2
    while True:
        pos = text.find(closer, pos)
        if pos < 0:
            return None
        if pos + 1 == len(text) or text[pos + 1].isspace():
            return pos + 1
        pos += 1


def _plain_default(text, start):
    """End index of a default made of non-blank characters and quoted stretches."""
    pos = start
    while pos < len(text) and not text[pos].isspace():
        if text[pos] in "'\"":
            end = text.find(text[pos], pos + 1)
            if end < 0:
                raise XacroException("unclosed quote in macro parameter default: %s" % text[start:])
            pos = end + 1
        else:
            pos += 1
    return pos


def parse_params(text):
    """[(name, default_spec or None)] of a macro's params attribute (see the module docstring)."""
    result = []
    pos, n = 0, len(text)
    while True:
        while pos < n and text[pos].isspace():
            pos += 1
        if pos >= n:
            return result
        start = pos
        while pos < n and not text[pos].isspace() and text[pos] not in ":=":
            pos += 1
        name = text[start:pos]
        # optional blanks, then ':=' or '=' introduce a default
        look = pos
        while look < n and text[look].isspace():
            look += 1
        if text.startswith(":=", look) or text.startswith("=", look):
            if not name:
                raise XacroException("macro parameter without a name in params=\"%s\"" % text)
            pos = look + (2 if text.startswith(":=", look) else 1)
            while pos < n and text[pos].isspace():
                pos += 1
            forward = None
            if text.startswith("^", pos):
                forward = name
                pos += 2 if text.startswith("^|", pos) else 1
            end = None
            if text.startswith("${", pos):
                end = _closing(text, pos, "{", "}")
            elif text.startswith("$(", pos):
                end = _closing(text, pos, "(", ")")
            if end is None:
                end = _plain_default(text, pos)
            default = text[pos:end] or None
            pos = end
            result.append((name, None if forward is None and default is None else (forward, default)))
        else:
            if pos < n and text[pos] in ":=":   # a stray ':' inside a name: keep it in the name
                while pos < n and not text[pos].isspace():
                    pos += 1
                name = text[start:pos]
            result.append((name, None))
