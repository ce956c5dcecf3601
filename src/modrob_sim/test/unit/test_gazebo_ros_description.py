"""Visuals, collisions and inertial origins parsed for markers and model properties; world files."""
import os

import pytest

from modrob_sim.errors import ModelError
from modrob_sim.gazebo_ros import description, world_file

HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = os.path.join(os.path.dirname(HERE), "fixtures", "sim")

URDF = """<robot name="r">
  <material name="red"><color rgba="1 0 0 1"/></material>
  <link name="base"><visual><origin xyz="0 0 0.1"/><geometry><box size="0.2 0.3 0.4"/></geometry>
    <material name="red"/></visual><collision><geometry><box size="0.2 0.3 0.4"/></geometry></collision>
    <inertial><origin xyz="0 0 0.05"/><mass value="1"/>
    <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>
    </inertial></link>
  <link name="tip"><visual><geometry><mesh filename="package://x/m.stl" scale="2 2 2"/></geometry>
  </visual></link>
  <gazebo reference="tip"><material>Gazebo/Blue</material></gazebo>
</robot>"""

SDF = """<sdf version="1.6"><world name="w"><include><uri>model://ground_plane</uri></include>
  <model name="table"><static>true</static><link name="top"><visual name="v"><pose>0 0 1 0 0 0</pose>
  <geometry><cylinder><radius>0.5</radius><length>0.04</length></cylinder></geometry>
  <material><diffuse>0 1 0 1</diffuse></material></visual></link></model></world></sdf>"""


def test_urdf_visuals_colours_and_inertial_origin():
    links = description.parse_links(URDF)
    base = links["base"].visuals[0]
    assert base.kind == "box" and base.size == (0.2, 0.3, 0.4) and base.rgba == (1, 0, 0, 1)
    assert base.origin[0] == (0.0, 0.0, 0.1)
    assert links["base"].collision_names == ["base_collision"]
    assert links["base"].inertial_origin[0] == (0.0, 0.0, 0.05)
    tip = links["tip"].visuals[0]
    assert tip.kind == "mesh" and tip.filename == "package://x/m.stl" and tip.scale == (2, 2, 2)
    assert tip.rgba == description.GAZEBO_MATERIALS["Gazebo/Blue"]


def test_sdf_model_in_world_and_builtin_ground_plane():
    table = description.parse_links(SDF, "table")["top"].visuals[0]
    assert table.kind == "cylinder" and table.size == (0.5, 0.04) and table.rgba == (0, 1, 0, 1)
    ground = description.parse_links(SDF, "ground_plane")
    assert ground["link"].visuals[0].kind == "plane"


def test_xml_kind():
    assert description.xml_kind(URDF) == "urdf"
    assert description.xml_kind(SDF) == "sdf"
    assert description.xml_kind("<robot") is None
    assert description.xml_kind("<html/>") is None


def test_world_physics_and_find_world():
    path = world_file.find_world("worlds/empty.world")
    with open(path) as f:
        phys = world_file.world_physics(f.read())
    assert phys["time_step"] == 0.001 and phys["gravity"] == (0.0, 0.0, -9.81)


def test_missing_world_names_what_was_tried():
    with pytest.raises(ModelError) as err:
        world_file.find_world("worlds/nope.world")
    assert "nope.world" in str(err.value) and "tried" in str(err.value)
