"""Stub description packages for the optional accessories a robot's xacro includes unconditionally.

Husky's and Jackal's xacro files include ``$(find lms1xx)/urdf/sick_lms1xx.urdf.xacro``,
``$(find flir_camera_description)/...``, ``$(find sick_tim)/...``,
``$(find pointgrey_camera_description)/...`` and more even when the accessory is switched off,
so xacro stops when those packages are not installed (Debian has none of them). For each package
that rospack cannot find, this writes a stub package (a package.xml and each included file as an
empty ``<robot>``) into a folder the user adds to ROS_PACKAGE_PATH. A stub defines no macros:
an accessory switched on still fails in xacro, naming the macro (install the real package then).

    rosrun modrob_sim stub_packages <robot.urdf.xacro> [more files] --into ~/stubs
    export ROS_PACKAGE_PATH=~/stubs:$ROS_PACKAGE_PATH
"""
import argparse
import os
import re
import sys

import rospkg

FIND = re.compile(r"\$\(find ([A-Za-z0-9_]+)\)(/[^\"'<>\s)]*)?")

PACKAGE_XML = """<?xml version="1.0"?>
<package format="2">
  <name>{name}</name>
  <version>0.0.0</version>
  <description>Stub made by modrob_sim's stub_packages: the files {user} includes, empty, so that
    its xacro expands without this optional accessory. Install the real {name} to use it.</description>
  <maintainer email="nobody@example.org">stub</maintainer>
  <license>none</license>
  <buildtool_depend>catkin</buildtool_depend>
</package>
"""
EMPTY_XACRO = """<?xml version="1.0"?>
<!-- stub of {name}{path} (modrob_sim stub_packages): defines nothing -->
<robot xmlns:xacro="http://www.ros.org/wiki/xacro"/>
"""


def missing_includes(files, rospack):
    """{package: set(paths)} of the $(find pkg)/path references, in the files and (recursively) in
    the files of existing packages they name, whose package rospack cannot find."""
    missing, seen, todo = {}, set(), [os.path.abspath(f) for f in files]
    while todo:
        path = todo.pop()
        if path in seen or not os.path.isfile(path):
            continue
        seen.add(path)
        with open(path, errors="replace") as f:
            text = f.read()
        for pkg, rel in FIND.findall(text):
            try:
                base = rospack.get_path(pkg)
            except rospkg.ResourceNotFound:
                missing.setdefault(pkg, set())
                if rel:
                    missing[pkg].add(rel)
                continue
            if rel and rel.endswith((".xacro", ".urdf")):
                todo.append(os.path.join(base, rel.lstrip("/")))
    return missing


def write_stubs(missing, into, user):
    """Write the stub packages; returns the list of folders written."""
    written = []
    for pkg, paths in sorted(missing.items()):
        root = os.path.join(into, pkg)
        os.makedirs(root, exist_ok=True)
        with open(os.path.join(root, "package.xml"), "w") as f:
            f.write(PACKAGE_XML.format(name=pkg, user=user))
        for rel in sorted(paths):
            if "$(" in rel:
                continue
            target = os.path.join(root, rel.lstrip("/"))
            os.makedirs(os.path.dirname(target), exist_ok=True)
            if rel.endswith((".xacro", ".urdf")) and not os.path.exists(target):
                with open(target, "w") as f:
                    f.write(EMPTY_XACRO.format(name=pkg, path=rel))
        written.append(root)
    return written


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+", help="xacro or launch files of the robot")
    ap.add_argument("--into", required=True, help="folder for the stub packages (add it to ROS_PACKAGE_PATH)")
    a = ap.parse_args(argv)
    missing = missing_includes(a.files, rospkg.RosPack())
    if not missing:
        print("stub_packages: every package the files include is installed; nothing to do")
        return 0
    user = ", ".join(os.path.basename(f) for f in a.files)
    for root in write_stubs(missing, os.path.expanduser(a.into), user):
        print("stub_packages: wrote stub package %s" % root)
    into = os.path.abspath(os.path.expanduser(a.into))
    print("stub_packages: now export ROS_PACKAGE_PATH=%s:$ROS_PACKAGE_PATH" % into)
    return 0


if __name__ == "__main__":
    sys.exit(main())
