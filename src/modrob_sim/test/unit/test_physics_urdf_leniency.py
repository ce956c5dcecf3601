"""Tier 1: the URDF read as leniently as Gazebo's URDF conversion reads it, each leniency said once.

- ``<gazebo>`` keys in attribute form (``<mu1 value="1.0"/>``, Husky and Jackal) mean the same as
  the element form (``<mu1>1.0</mu1>``); the attribute wins when both are given;
- a ``<gazebo reference>`` naming no link or joint (UR's ``ee_link``) is ignored with a warning,
  and the model's other blocks still apply.
"""
import math

import pytest

from modrob_sim.physics import World
from modrob_sim.physics.urdf_reader import read_urdf

LINK = """<link name="{name}"><inertial><mass value="1"/>
  <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>"""
WHEEL_JOINT = """<joint name="axle" type="continuous"><parent link="base"/><child link="wheel"/>
  <origin xyz="0 0.2 0"/><axis xyz="0 1 0"/></joint>"""

ELEMENT_FORM = """<gazebo reference="wheel"><mu1>0.3</mu1><mu2>0.8</mu2><kp>100000.0</kp><kd>10.0</kd>
  <fdir1>1 0 0</fdir1><maxVel>0.5</maxVel><minDepth>0.002</minDepth><material>Gazebo/Black</material>
  <selfCollide>true</selfCollide><maxContacts>3</maxContacts></gazebo>
  <gazebo reference="axle"><implicitSpringDamper>1</implicitSpringDamper></gazebo>
  <gazebo><static>false</static></gazebo>"""
ATTRIBUTE_FORM = """<gazebo reference="wheel"><mu1 value="0.3"/><mu2 value="0.8"/><kp value="100000.0"/>
  <kd value="10.0"/><fdir1 value="1 0 0"/><maxVel value="0.5"/><minDepth value="0.002"/>
  <material value="Gazebo/Black"/><selfCollide value="true"/><maxContacts value="3"/></gazebo>
  <gazebo reference="axle"><implicitSpringDamper value="1"/></gazebo>
  <gazebo><static value="false"/></gazebo>"""


def robot(gazebo_blocks, name="r"):
    return "<robot name='%s'>%s%s%s%s</robot>" % (name, LINK.format(name="base"), LINK.format(name="wheel"),
                                                  WHEEL_JOINT, gazebo_blocks)


class Warnings(object):
    def __init__(self):
        self.messages = {}

    def __call__(self, key, message):
        self.messages.setdefault(key, message)


def surface_of(desc, link):
    s = desc.links[link].surface
    return (s.mu1, s.mu2, s.kp, s.kd, s.fdir1, s.max_vel, s.min_depth, s.max_contacts)


def test_attribute_form_reads_as_the_element_form():
    warn_e, warn_a = Warnings(), Warnings()
    e = read_urdf("r", robot(ELEMENT_FORM), warn_e)
    a = read_urdf("r", robot(ATTRIBUTE_FORM), warn_a)
    expected = (0.3, 0.8, 100000.0, 10.0, (1.0, 0.0, 0.0), 0.5, 0.002, 3)
    assert surface_of(a, "wheel") == surface_of(e, "wheel") == expected
    assert a.links["wheel"].material == e.links["wheel"].material == "Gazebo/Black"
    assert a.links["wheel"].self_collide is e.links["wheel"].self_collide is True
    # stored elements (read later by joints, plugins) carry the value as their text
    assert a.joints["axle"].extra["implicitSpringDamper"].text == "1"
    assert not warn_e.messages
    # one warning per model and tag, naming the model and both forms
    text = warn_a.messages["urdf-value-attribute:r:mu1"]
    assert "model 'r'" in text and '<mu1 value="0.3"/>' in text and "<mu1>0.3</mu1>" in text
    assert len([k for k in warn_a.messages if k.startswith("urdf-value-attribute:r:")]) == 12


def test_the_value_attribute_wins_over_text_as_in_gazebo():
    a = read_urdf("r", robot('<gazebo reference="wheel"><mu1 value="0.25">0.9</mu1></gazebo>'), Warnings())
    assert a.links["wheel"].surface.mu1 == 0.25


def test_plugin_and_sensor_blocks_are_left_as_written():
    blocks = ('<gazebo><plugin name="p" filename="libx.so"><param value="keep"/></plugin></gazebo>'
              '<gazebo reference="base"><sensor type="ray" name="s"><pose value="1"/></sensor></gazebo>')
    d = read_urdf("r", robot(blocks), Warnings())
    assert d.plugins[0].element.find("param").text is None
    assert d.links["base"].sensors[0].find("pose").text is None


def test_a_bad_value_in_attribute_form_is_refused_naming_it():
    with pytest.raises(Exception) as err:
        read_urdf("r", robot('<gazebo reference="wheel"><mu1 value="slippery"/></gazebo>'), Warnings())
    assert "mu1" in str(err.value) and "slippery" in str(err.value) and "model 'r'" in str(err.value)


def test_a_reference_to_no_link_is_ignored_with_one_warning_and_the_rest_applies():
    warn = Warnings()
    blocks = ('<gazebo reference="ee_link"><material>Gazebo/Red</material></gazebo>'
              '<gazebo reference="wheel"><mu1>0.4</mu1></gazebo>'
              '<gazebo reference="ee_link"><selfCollide>true</selfCollide></gazebo>')
    d = read_urdf("ur", robot(blocks, "ur"), warn)
    assert d.links["wheel"].surface.mu1 == 0.4
    keys = [k for k in warn.messages if k.startswith("urdf-dangling-reference:")]
    assert keys == ["urdf-dangling-reference:ur:ee_link"]
    text = warn.messages[keys[0]]
    assert "<gazebo reference='ee_link'>" in text and "model 'ur'" in text and "ignored" in text


def test_a_world_spawns_both_and_the_attribute_form_grips_the_same(caplog):
    """The same box with mu1 0.2 / mu2 0.2 on a 20 degree ramp slides the same way in both forms."""
    angle = math.radians(20)
    moved = {}
    for form in ("element", "attribute"):
        world = World()
        gz = ('<gazebo reference="box"><mu1>0.2</mu1><mu2>0.2</mu2></gazebo>' if form == "element" else
              '<gazebo reference="box"><mu1 value="0.2"/><mu2 value="0.2"/></gazebo>'
              '<gazebo reference="nowhere"><mu1>5</mu1></gazebo>')
        world.add_urdf("ramp", "<robot name='ramp'><link name='ramp'><collision><origin rpy='0 %r 0'/>"
                       "<geometry><box size='4 2 0.1'/></geometry></collision></link><gazebo><static>true"
                       "</static></gazebo></robot>" % angle)
        box = world.add_urdf("box", "<robot name='box'>%s%s</robot>" % (LINK.format(name="box"), gz),
                             pose=((0.1 * math.sin(angle), 0, 0.05 + 0.1 * math.cos(angle)),
                                   (0, math.sin(angle / 2), 0, math.cos(angle / 2))))
        p0 = box.pose[0]
        world.step(300)
        moved[form] = math.dist(p0, box.pose[0])
        world.close()
    assert moved["element"] > 0.05            # tan 20 deg = 0.36 > 0.2: it slides
    assert moved["attribute"] == pytest.approx(moved["element"], abs=1e-9)
