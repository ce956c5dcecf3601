"""Visuals, collision names and inertial origins for markers and model properties come from the
physics core's one reader; world files."""
import os

import pytest

from modrob_sim.errors import ModelError
from modrob_sim.gazebo_ros import markers, world_file
from modrob_sim.gazebo_ros import resources
from modrob_sim.gazebo_ros.resources import ResourceResolver
from modrob_sim.gazebo_ros.services.models import xml_kind
from modrob_sim.physics import World

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
  <joint name="fix" type="fixed"><parent link="base"/><child link="tip"/></joint>
  <gazebo reference="tip"><material>Gazebo/Blue</material></gazebo>
</robot>"""

SDF = """<sdf version="1.6"><world name="w"><include><uri>model://ground_plane</uri></include>
  <model name="table"><static>true</static><link name="top"><visual name="v"><pose>0 0 1 0 0 0</pose>
  <geometry><cylinder><radius>0.5</radius><length>0.04</length></cylinder></geometry>
  <material><diffuse>0 1 0 1</diffuse></material></visual></link></model></world></sdf>"""


def test_urdf_visuals_colours_and_inertial_origin_come_from_the_core():
    w = World(time_step=0.001)
    try:
        m = w.add_urdf("r", URDF.replace('<mesh filename="package://x/m.stl" scale="2 2 2"/>',
                                         '<sphere radius="0.1"/>'))
        vis = markers.WorldMarkers(w, "all")._model_visuals(m)
        base = vis["base"][0]
        assert base.kind == "box" and base.size == (0.2, 0.3, 0.4) and base.rgba == (1, 0, 0, 1)
        assert base.origin[0] == (0.0, 0.0, 0.1)
        assert m.links["base"].collision_names == ["base_collision"]
        assert m.links["base"].inertial_origin[0] == (0.0, 0.0, 0.05)
        assert vis["tip"][0].rgba == markers.GAZEBO_MATERIALS["Gazebo/Blue"]
    finally:
        w.close()


def test_sdf_model_in_world_and_builtin_ground_plane():
    w = World(time_step=0.001)
    try:
        models = {m.name: m for m in w.add_sdf(SDF)}
        wm = markers.WorldMarkers(w, "all")
        table = wm._model_visuals(models["table"])["top"][0]
        assert table.kind == "cylinder" and table.size == (0.5, 0.04) and table.rgba == (0, 1, 0, 1)
        assert wm._model_visuals(models["ground_plane"])["link"][0].kind == "plane"
    finally:
        w.close()


def test_xml_kind():
    assert xml_kind(URDF) == "urdf"
    assert xml_kind(SDF) == "sdf"
    assert xml_kind("<robot") is None
    assert xml_kind("<html/>") is None


def test_world_physics_and_find_world():
    path = world_file.find_world("worlds/empty.world", ResourceResolver())
    with open(path) as f:
        phys = world_file.world_physics(f.read())
    assert phys["time_step"] == 0.001 and phys["gravity"] == (0.0, 0.0, -9.81)


def test_missing_world_names_what_was_tried():
    with pytest.raises(ModelError) as err:
        world_file.find_world("worlds/nope.world", ResourceResolver())
    assert "nope.world" in str(err.value) and "looked in the current folder" in str(err.value)
    assert resources.PACKAGE_DIR in str(err.value)      # modrob_sim's own worlds/ were searched
