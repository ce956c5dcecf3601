"""Older SDF read as Gazebo 11 reads it: converted to the current element form first.

- SDF 1.0 (``<gazebo version="1.0">``) wrote values as attributes: ``<origin pose="..."/>``,
  ``<inertial mass="1">``, ``<box size="1 1 1"/>``, ``<parent link="a"/>``,
  ``<physics><gravity xyz="..."/><ode><solver type="quick" dt="0.001" iters="10"/>``. sdformat
  converts it to 1.2 by moving each attribute into a child element of the same name (``name``,
  ``filename``, and ``type`` except on ``<solver>``, stay attributes), an element whose value was
  its one attribute takes it as text (``<gravity xyz>``, ``<parent link>``, ``<diffuse rgba>``
  ...), ``<origin pose>`` becomes ``<pose>``, a link's ``<damping>`` its ``<velocity_decay>``,
  a material's ``script`` attribute its ``<script>``; a mesh's file name becomes its ``<uri>``.
- SDF before 1.4 kept the step in ``<physics><ode><solver><dt>`` and the rate in
  ``<physics><update_rate>``: they become ``<physics><max_step_size>`` and
  ``<real_time_update_rate>``.

``upgrade(root, label, warn)`` returns the converted root Element (the same one, changed in place)
and warns once per file that it converted it.
"""
import xml.etree.ElementTree as ET

from .xml_util import local

#: elements whose one attribute was their value in SDF 1.0: tag -> attribute
VALUE_ATTRIBUTE = {"gravity": "xyz", "parent": "link", "child": "link", "ambient": "rgba",
                   "background": "rgba", "shadows": "enabled", "grid": "enabled", "diffuse": "rgba",
                   "specular": "rgba", "emissive": "rgba", "direction": "xyz", "horizontal_fov": "angle"}
#: attributes that stay attributes in every SDF version
KEEP = ("name", "filename", "version")


def _version(text):
    try:
        return tuple(int(x) for x in str(text).strip().split("."))
    except ValueError:
        return None


def _child(elem, tag):
    for c in elem:
        if local(c.tag) == tag:
            return c
    return None


def _sub(parent, tag, text, index=None):
    e = ET.Element(tag)
    e.text = text
    e.tail = "\n"
    if index is None:
        parent.append(e)
    else:
        parent.insert(index, e)
    return e


def _from_1_0(elem, parent_tag=None):
    """SDF 1.0 -> 1.2, in place, for ``elem`` and everything below it."""
    tag = local(elem.tag)
    for c in list(elem):
        _from_1_0(c, tag)
    if tag == "origin" and elem.get("pose") is not None:
        elem.tag = "pose"
        elem.text = elem.attrib.pop("pose")
        return
    if tag in VALUE_ATTRIBUTE and elem.get(VALUE_ATTRIBUTE[tag]) is not None and not len(elem):
        elem.text = elem.attrib.pop(VALUE_ATTRIBUTE[tag])
        return
    if tag == "damping" and parent_tag == "link":
        elem.tag = "velocity_decay"
    for attr in list(elem.attrib):
        if attr in KEEP or (attr == "type" and tag != "solver") or attr.startswith("{"):
            continue
        value = elem.attrib.pop(attr)
        if tag == "material" and attr == "script":
            _sub(_sub(elem, "script", None), "name", value)
        else:
            _sub(elem, attr, value)
    if tag == "mesh" and elem.get("filename") is not None:
        _sub(elem, "uri", elem.attrib.pop("filename"))


def _from_1_3(root):
    """SDF < 1.4: <physics><ode><solver><dt> -> <physics><max_step_size>, <physics><update_rate>
    -> <real_time_update_rate>."""
    for physics in root.iter():
        if local(physics.tag) != "physics":
            continue
        rate = _child(physics, "update_rate")
        if rate is not None and _child(physics, "real_time_update_rate") is None:
            rate.tag = "real_time_update_rate"
        ode = _child(physics, "ode")
        solver = _child(ode, "solver") if ode is not None else None
        dt = _child(solver, "dt") if solver is not None else None
        if dt is not None and _child(physics, "max_step_size") is None:
            solver.remove(dt)
            _sub(physics, "max_step_size", dt.text, 0)


def upgrade(root, label, warn):
    """``root`` (a parsed SDF document) in the current element form; see the module's text."""
    tag = local(root.tag)
    version = _version(root.get("version")) if tag in ("gazebo", "sdf") else None
    if tag == "gazebo":
        warn("sdf-version:%s" % label, "%s: <gazebo version=\"%s\"> (SDF 1.0) read as Gazebo 11 converts it "
             "(attributes to elements)" % (label, root.get("version", "")))
        _from_1_0(root)
        root.tag = "sdf"
        version = (1, 2)
    if version is not None and version < (1, 4):
        _from_1_3(root)
    return root
