"""KDL trees from URDF with ROS's ``kdl_parser_py.urdf`` API::

    from kdl_parser_py.urdf import treeFromFile, treeFromParam, treeFromString, treeFromUrdfModel
    ok, tree = treeFromString(urdf_xml)          # tree: PyKDL.Tree, segments named by link

Every function returns ``(ok, tree)`` as ROS's does; ``ok`` is False (and ``tree`` None) when the
description cannot be converted, with the reason logged unless ``quiet``. The conversion follows
kdl_parser: one segment per non-root link, its joint the link's parent joint (revolute and
continuous -> RotAxis, prismatic -> TransAxis, fixed -> Fixed; floating and planar become fixed with
a warning), the tip frame the joint origin, the inertia the link's inertial about its COM. It is
:mod:`modrob_kinematics.kdl_urdf`'s, which keeps the bookkeeping (joint order, limits) that the
workspace's FK and IK helpers use.
"""
import logging

import rospy

from modrob_kinematics import kdl_urdf
from modrob_kinematics.errors import UrdfError

_log = logging.getLogger("kdl_parser_py")


def _convert(read, what, quiet):
    try:
        return True, kdl_urdf.tree_from_urdf_model(read()).tree
    except UrdfError as err:
        reason = str(err)
    except Exception as err:  # noqa: B902 - urdf_parser_py raises lxml, assertion and value errors
        reason = "not a valid URDF: %s" % err
    if not quiet:
        _log.error("kdl_parser_py: cannot build a KDL tree from %s: %s", what, reason)
    return False, None


def treeFromUrdfModel(robot_model, quiet=False):  # noqa: N802 - ROS's name
    """``(ok, PyKDL.Tree)`` from an ``urdf_parser_py.urdf.URDF`` (Robot) object."""
    return _convert(lambda: robot_model, "robot '%s'" % getattr(robot_model, "name", "?"), quiet)


def treeFromString(xml, quiet=False):  # noqa: N802 - ROS's name
    """``(ok, PyKDL.Tree)`` from a URDF document in a string."""
    return _convert(lambda: kdl_urdf.parse_urdf(xml), "a URDF string", quiet)


def treeFromFile(filename, quiet=False):  # noqa: N802 - ROS's name
    """``(ok, PyKDL.Tree)`` from a URDF file."""
    try:
        with open(filename) as f:
            xml = f.read()
    except OSError as err:
        if not quiet:
            _log.error("kdl_parser_py: cannot read URDF file '%s': %s", filename, err.strerror)
        return False, None
    return _convert(lambda: kdl_urdf.parse_urdf(xml), "file '%s'" % filename, quiet)


def treeFromParam(param, quiet=False):  # noqa: N802 - ROS's name
    """``(ok, PyKDL.Tree)`` from a URDF on the parameter server (e.g. ``robot_description``)."""
    try:
        xml = rospy.get_param(param)
    except KeyError:
        if not quiet:
            _log.error("kdl_parser_py: parameter '%s' is not set: load a URDF into it first", param)
        return False, None
    return _convert(lambda: kdl_urdf.parse_urdf(xml), "parameter '%s'" % param, quiet)
