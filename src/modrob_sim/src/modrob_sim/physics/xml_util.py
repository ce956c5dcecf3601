"""Checked number parsing for the URDF and SDF readers: every error names the element, the
attribute and the model, so the user knows what to fix."""
import logging
import math
import xml.etree.ElementTree as ET

from ..errors import ModelError

LOG = logging.getLogger("modrob_sim.physics")


def parse_xml(text, model_name, kind):
    if not isinstance(text, str):
        if isinstance(text, bytes):
            text = text.decode("utf-8", "replace")
        else:
            raise ModelError("model '%s': %s description must be XML text, got %s"
                             % (model_name, kind, type(text).__name__))
    if not text.strip():
        raise ModelError("model '%s': the %s description is empty" % (model_name, kind))
    try:
        return ET.fromstring(text.encode("utf-8") if text.lstrip().startswith("<?xml") else text)
    except ET.ParseError as e:
        raise ModelError("model '%s': malformed %s XML: %s" % (model_name, kind, e))


class Reader(object):
    """Number parsing bound to a model name (for the messages)."""

    def __init__(self, model_name, kind):
        self.model = model_name
        self.kind = kind

    def fail(self, where, msg):
        raise ModelError("model '%s' (%s), %s: %s" % (self.model, self.kind, where, msg))

    def floats(self, text, n, where, what):
        if text is None:
            self.fail(where, "%s is missing" % what)
        if "${" in text or "$(" in text:
            self.fail(where, "%s = '%s' looks like unexpanded xacro: run xacro first" % (what, text))
        parts = text.split()
        if n is not None and len(parts) != n:
            self.fail(where, "%s = '%s' must have %d numbers" % (what, text, n))
        try:
            vals = tuple(float(p) for p in parts)
        except ValueError:
            self.fail(where, "%s = '%s' is not a number list" % (what, text))
        for v in vals:
            if not math.isfinite(v):
                self.fail(where, "%s = '%s' is not finite" % (what, text))
        return vals

    def float(self, text, where, what, default=None):
        if text is None:
            if default is None:
                self.fail(where, "%s is missing" % what)
            return default
        return self.floats(text.strip(), 1, where, what)[0]

    def int(self, text, where, what):
        """A whole number (Gazebo writes counts such as <maxContacts> as 10 or 10.0)."""
        v = self.float(text, where, what)
        if v != int(v):
            self.fail(where, "%s = '%s' is not a whole number" % (what, text))
        return int(v)

    def bool(self, text, where, what):
        t = (text or "").strip().lower()
        if t in ("1", "true", "yes", "on"):
            return True
        if t in ("0", "false", "no", "off"):
            return False
        self.fail(where, "%s = '%s' is not a boolean (true/false)" % (what, text))


def local(tag):
    """Tag without an XML namespace ('{ns}x' -> 'x'); xacro output sometimes keeps namespaces."""
    if isinstance(tag, str) and tag.startswith("{"):
        return tag.split("}", 1)[1]
    return tag
