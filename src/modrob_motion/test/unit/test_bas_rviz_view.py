"""Tier 1: RViz's Bulbs and Slides view (config/bulbs_and_slides.rviz, what gui:=true opens) holds
the whole one-robot scene: the arm standing straight up at the start and the table down to its
feet. Projected with RViz's orbit camera; the old view (sim.rviz's) cut the arm's top off."""
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import yaml

from modrob_build.build import build_robot_set
from modrob_build.robot_set_config import RobotSpec
from modrob_kinematics import kdl_urdf

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
CONFIG = os.path.join(SRC, "modrob_motion", "config", "bulbs_and_slides.rviz")
LAYOUT = os.path.join(SRC, "modrob_description", "worlds", "bulbs_and_slides_layout.yaml")
FOV_Y = math.pi / 4          # RViz's 3D view: OGRE's default vertical field of view
PANEL = (1200 - 360, 800 - 110)   # the config's window less the Displays dock, tool and status bars
TABLE = (2.0, 1.2)           # docs/bulbs_and_slides.md, "The world"


def in_view(view, point):
    """(x, y) of ``point`` in the view's normalised image coordinates (inside: both within +-1)."""
    focal = np.array([view["Focal Point"][k] for k in "XYZ"], float)
    yaw, pitch, distance = view["Yaw"], view["Pitch"], view["Distance"]
    eye = focal + distance * np.array([math.cos(yaw) * math.cos(pitch), math.sin(yaw) * math.cos(pitch),
                                       math.sin(pitch)])
    forward = (focal - eye) / np.linalg.norm(focal - eye)
    right = np.cross(forward, [0, 0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    d = np.asarray(point, float) - eye
    depth = d @ forward
    half = math.tan(FOV_Y / 2) * depth
    return (d @ right) / (half * PANEL[0] / PANEL[1]), (d @ up) / half


def scene_points():
    """The arm's link frames at its start (every joint 0: straight up) and the table's corners."""
    with open(LAYOUT) as f:
        robot = yaml.safe_load(f)["layouts"]["one_robot"]["robots"][0]
    result = build_robot_set([RobotSpec(",".join(map(str, robot["order"])), tuple(robot["base"]))],
                             gripper=True, gains="computed", out_dir="/nonexistent")
    urdf = next(text for name, text in result.files.items() if name.endswith(".urdf"))
    tree = kdl_urdf.tree_from_urdf_string(urdf)
    fk = kdl_urdf.TreeFkSolverPos(tree)
    links = [kdl_urdf.frame_to_matrix(fk.jnt_to_cart({}, name))[:3, 3] for name in tree.segments]
    top = max(p[2] for p in links)
    corners = [(sx * TABLE[0] / 2, sy * TABLE[1] / 2, z)
               for sx in (-1, 1) for sy in (-1, 1) for z in (0.0, 1.02)]
    return links, top, corners


def test_the_launch_file_opens_rviz_with_the_scenario_view():
    launch = ET.parse(os.path.join(SRC, "modrob_motion", "launch", "bulbs_and_slides.launch")).getroot()
    given = {a.get("name"): a.get("value") for a in launch.iter("arg") if a.get("value")}
    assert given["rviz_config"] == "$(find modrob_motion)/config/bulbs_and_slides.rviz"
    build = ET.parse(os.path.join(SRC, "modrob_build", "launch", "urdf_and_gazebo.launch")).getroot()
    assert any(a.get("name") == "rviz_config" and a.get("value") == "$(arg rviz_config)"
               for a in build.iter("arg"))


def test_the_view_holds_the_standing_arm_and_the_table():
    links, top, corners = scene_points()
    assert top > 3.0, "the one-robot arm stands %.2f m high: not the 2.2 m arm on the 1.02 m table?" % top
    with open(CONFIG) as f:
        view = yaml.safe_load(f)["Visualization Manager"]["Views"]["Current"]
    # the link frames with a margin (the fingers reach beyond the last frame), the table's corners
    # (its legs stand a little inside them) within the view
    for points, limit in ((links, 0.9), (corners, 1.0)):
        for point in points:
            x, y = in_view(view, point)
            assert abs(x) < limit and abs(y) < limit, \
                "%s is outside the view (%.2f, %.2f)" % (tuple(point), x, y)
    with open(os.path.join(SRC, "modrob_sim", "config", "sim.rviz")) as f:   # the check sees a crop
        plain = yaml.safe_load(f)["Visualization Manager"]["Views"]["Current"]
    assert max(abs(in_view(plain, p)[1]) for p in links) > 1.0


def test_the_build_launch_view_holds_the_readme_robots():
    """urdf_and_gazebo.launch gui:=true (config/robots.rviz of modrob_build): the README's two
    robots (bases 0 and 0.8 m after the safety distance, on 1.02 m) from the floor to their tops."""
    launch = ET.parse(os.path.join(SRC, "modrob_build", "launch", "urdf_and_gazebo.launch")).getroot()
    default = next(a.get("default") for a in launch.iter("arg") if a.get("name") == "rviz_config")
    assert default == "$(find modrob_build)/config/robots.rviz"
    specs = [RobotSpec("59,3,55,63,57,5", (x, 0.0, 1.02)) for x in (0.0, 0.8)]
    result = build_robot_set(specs, gripper=True, gains="computed", out_dir="/nonexistent")
    points = []
    for name, text in result.files.items():
        if name.endswith(".urdf"):
            tree = kdl_urdf.tree_from_urdf_string(text)
            fk = kdl_urdf.TreeFkSolverPos(tree)
            points += [kdl_urdf.frame_to_matrix(fk.jnt_to_cart({}, s))[:3, 3] for s in tree.segments]
    assert len(points) > 10 and max(p[2] for p in points) > 2.0
    points += [(p[0], p[1], 0.0) for p in points]          # and the floor below them
    with open(os.path.join(SRC, "modrob_build", "config", "robots.rviz")) as f:
        view = yaml.safe_load(f)["Visualization Manager"]["Views"]["Current"]
    for point in points:
        x, y = in_view(view, point)
        assert abs(x) < 0.9 and abs(y) < 0.9, "%s is outside the view (%.2f, %.2f)" % (tuple(point), x, y)
    with open(os.path.join(SRC, "modrob_sim", "config", "sim.rviz")) as f:   # the check sees a crop
        plain = yaml.safe_load(f)["Visualization Manager"]["Views"]["Current"]
    assert max(abs(in_view(plain, p)[1]) for p in points) > 1.0
