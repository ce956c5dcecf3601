"""Tier 1: stub_packages writes stub packages for the accessory packages a robot's xacro includes
unconditionally (Husky's lms1xx, Jackal's sick_tim ...), so that xacro expands without them; found
recursively through the packages that exist; an installed package is never stubbed."""
import os
import subprocess

import rospkg

from modrob_sim.gazebo_ros import stub_packages

ROBOT = """<?xml version="1.0"?>
<robot name="rover" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find rover_description)/urdf/accessories.urdf.xacro"/>
  <xacro:include filename="$(find lidar_vendor_description)/urdf/lidar.urdf.xacro"/>
  <link name="base_link"/>
  <xacro:if value="$(optenv ROVER_LIDAR false)"><xacro:vendor_lidar parent="base_link"/></xacro:if>
</robot>
"""
ACCESSORIES = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find camera_vendor_description)/urdf/cams/flea.urdf.xacro"/>
  <xacro:macro name="mount"><link name="mount"/></xacro:macro>
</robot>
"""


def package(root, name, files):
    d = os.path.join(root, name)
    os.makedirs(d)
    with open(os.path.join(d, "package.xml"), "w") as f:
        f.write('<?xml version="1.0"?><package format="2"><name>%s</name><version>0.0.1</version>'
                '<description>fixture</description><maintainer email="fixture@example.org">a</maintainer>'
                '<license>BSD</license><buildtool_depend>catkin</buildtool_depend></package>' % name)
    for rel, text in files.items():
        os.makedirs(os.path.dirname(os.path.join(d, rel)), exist_ok=True)
        with open(os.path.join(d, rel), "w") as f:
            f.write(text)
    return d


def test_stubs_make_the_xacro_expand(tmp_path, monkeypatch):
    src, stubs = str(tmp_path / "src"), str(tmp_path / "stubs")
    pdir = package(src, "rover_description", {"urdf/rover.urdf.xacro": ROBOT,
                                              "urdf/accessories.urdf.xacro": ACCESSORIES})
    top = os.path.join(pdir, "urdf", "rover.urdf.xacro")
    rospack = rospkg.RosPack(ros_paths=[src])
    missing = stub_packages.missing_includes([top], rospack)
    assert missing == {"lidar_vendor_description": {"/urdf/lidar.urdf.xacro"},
                       "camera_vendor_description": {"/urdf/cams/flea.urdf.xacro"}}
    written = stub_packages.write_stubs(missing, stubs, "rover.urdf.xacro")
    assert sorted(os.path.basename(w) for w in written) == ["camera_vendor_description",
                                                            "lidar_vendor_description"]
    assert os.path.isfile(os.path.join(stubs, "camera_vendor_description", "urdf", "cams",
                                       "flea.urdf.xacro"))
    path = os.pathsep.join([stubs, src, os.environ.get("ROS_PACKAGE_PATH", "")])
    env = dict(os.environ, ROS_PACKAGE_PATH=path)
    env.pop("ROVER_LIDAR", None)
    run = subprocess.run(["xacro", top], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert run.returncode == 0, run.stderr
    assert '<link name="base_link"/>' in run.stdout
    # nothing is missing any more once the stubs are on the path
    assert stub_packages.missing_includes([top], rospkg.RosPack(ros_paths=[stubs, src])) == {}


def test_command_line_says_what_it_wrote(tmp_path, capsys, monkeypatch):
    src = str(tmp_path / "src")
    pdir = package(src, "rover_description", {"urdf/rover.urdf.xacro": ROBOT,
                                              "urdf/accessories.urdf.xacro": ACCESSORIES})
    monkeypatch.setenv("ROS_PACKAGE_PATH", src)
    top = os.path.join(pdir, "urdf", "rover.urdf.xacro")
    assert stub_packages.main([top, "--into", str(tmp_path / "s")]) == 0
    out = capsys.readouterr().out
    assert "wrote stub package %s" % os.path.join(str(tmp_path / "s"), "lidar_vendor_description") in out
    assert "export ROS_PACKAGE_PATH=%s:$ROS_PACKAGE_PATH" % str(tmp_path / "s") in out
