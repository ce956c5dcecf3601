"""The one exception type xacro raises, and its output to stderr (plain, or coloured on a tty)."""
import sys


class XacroException(Exception):
    """A processing error. ``str()`` joins the message, the wrapped exception and a suffix
    (for example the expression that was being evaluated)."""

    def __init__(self, msg=None, suffix=None, exc=None, macro=None):
        super().__init__(msg)
        self.suffix = suffix
        self.exc = exc
        self.macros = [] if macro is None else [macro]

    def __str__(self):
        parts = [super().__str__(), self.exc, self.suffix]
        return " ".join(str(p) for p in parts if p is not None and str(p) not in ("", "None"))


_COLOURS = {"red": 91, "yellow": 93}


def _colourise(text, colour, stream, prefix):
    code = _COLOURS.get(colour, colour)
    if code and getattr(stream, "isatty", lambda: False)():
        return "\033[%dm%s\033[0m" % (code, text)
    return (prefix or "") + text


def message(msg, *args, **kwargs):
    """Print msg and args on stderr (``color=`` an ANSI code or 'red'/'yellow' on a terminal)."""
    stream = kwargs.get("file") or sys.stderr
    print(_colourise(str(msg), kwargs.get("color"), stream, kwargs.get("alt_text")), *args, file=stream)


def warning(*args, **kwargs):
    kwargs.setdefault("color", "yellow")
    kwargs.setdefault("alt_text", "warning: ")
    message(*args, **kwargs)


def error(*args, **kwargs):
    kwargs.setdefault("color", "red")
    kwargs.setdefault("alt_text", "error: ")
    message(*args, **kwargs)
