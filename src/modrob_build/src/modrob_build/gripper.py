"""Attach the gripper (modrob_description/urdf/gripper.xacro) to a generated arm through xacro.

The arm's <robot> element gets an <xacro:include> of the macro file and a call
<xacro:modrob_gripper prefix=... parent=<ee_link> grip_force=.../>; xacro (its Python API)
expands it, and the result is re-serialised like the arm alone, so the output is deterministic.
"""
import math
import os
import xml.dom.minidom
import xml.etree.ElementTree as ET

from modrob_build.errors import BuildError
from modrob_build.module_database import default_database_path
from modrob_build.urdf_writer import fmt, to_text

XACRO_NS = "http://www.ros.org/wiki/xacro"
DEFAULT_GRIP_FORCE = 3.0
MAX_STABLE_GRIP_FORCE = 7.0   # tested stable (the seed saw crashes above 7 N)
MAX_GRIP_FORCE = 10.0
GRIPPER_JOINTS = ("gripper_finger1_joint", "gripper_finger2_joint")
# finger 2 is a <mimic> of finger 1 (a parallel gripper's coupling): one actuator, one controller
GRIPPER_ACTUATED_JOINTS = ("gripper_finger1_joint",)


def default_gripper_path():
    return os.path.join(os.path.dirname(os.path.dirname(default_database_path())), "urdf",
                        "gripper.xacro")


def check_grip_force(force):
    """Validated grip force in N; returns (force, warning or None)."""
    try:
        force = float(force)
    except (TypeError, ValueError):
        raise BuildError("grip force must be a number of newtons, not %r" % (force,))
    if not math.isfinite(force) or force <= 0.0 or force > MAX_GRIP_FORCE:
        raise BuildError("grip force %r N is outside (0, %g] N; the default is %g N and forces up to "
                         "%g N are tested stable" % (force, MAX_GRIP_FORCE, DEFAULT_GRIP_FORCE,
                                                     MAX_STABLE_GRIP_FORCE))
    warning = None
    if force > MAX_STABLE_GRIP_FORCE:
        warning = ("grip force %g N is above the %g N tested stable; grasps may be unstable"
                   % (force, MAX_STABLE_GRIP_FORCE))
    return force, warning


def _parse_with_comments(text):
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
    return ET.fromstring(text, parser=parser)


def attach_gripper(robot_root, prefix, parent, grip_force=DEFAULT_GRIP_FORCE, gripper_path=None):
    """URDF text of robot_root (an ElementTree <robot> element) with the gripper attached."""
    try:
        import xacro
    except ImportError:
        raise BuildError("the gripper needs the workspace's xacro package (src/xacro): "
                         "source scripts/env.sh first")
    gripper_path = gripper_path or default_gripper_path()
    if not os.path.isfile(gripper_path):
        raise BuildError("gripper macro file %s not found" % gripper_path)
    root = ET.fromstring(ET.tostring(robot_root))   # a copy
    root.set("xmlns:xacro", XACRO_NS)
    ET.SubElement(root, "xacro:include", filename=gripper_path)
    ET.SubElement(root, "xacro:modrob_gripper", prefix=prefix, parent=parent,
                  grip_force=fmt(grip_force))
    source = ET.tostring(root, encoding="unicode")
    try:
        doc = xacro.parse(source)
        xacro.process_doc(doc, mappings={})
    except (xacro.XacroException, xml.parsers.expat.ExpatError) as e:
        raise BuildError("xacro could not expand the gripper macro %s: %s" % (gripper_path, e))
    expanded = _parse_with_comments(doc.documentElement.toxml())
    for key in list(expanded.attrib):
        if key.startswith("xmlns"):
            del expanded.attrib[key]
    for el in expanded.iter():
        if isinstance(el.tag, str):
            el.text = el.text.strip() if el.text and el.text.strip() else None
            el.tail = None
    return to_text(expanded)
