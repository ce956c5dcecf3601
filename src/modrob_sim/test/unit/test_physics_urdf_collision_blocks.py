"""Tier 1: a ``<gazebo reference="link"><collision>`` block, as sdformat reads it for Gazebo 11: its
``<max_contacts>`` and ``<surface>`` go into each of the link's collisions (franka_description's
fingers give their mu 1.13, max_vel 0, min_depth 1 mm and 10 contacts this way), the block's own
tags such as ``<mu1>`` after them; a bad value names the link."""
import pytest

from modrob_sim.errors import ModelError
from modrob_sim.physics import World
from modrob_sim.physics.urdf_reader import read_urdf

FINGER = """<robot name="r"><link name="finger"><inertial><mass value="0.015"/>
  <inertia ixx="2e-6" ixy="0" ixz="0" iyy="2e-6" iyz="0" izz="8e-7"/></inertial>
  <collision><geometry><box size="0.02 0.015 0.02"/></geometry></collision>
  <collision><origin xyz="0 0 0.03"/><geometry><box size="0.02 0.01 0.02"/></geometry></collision></link>
  %s</robot>"""
BLOCK = """<gazebo reference="finger"><collision><max_contacts>10</max_contacts><surface>
  <contact><ode><max_vel>0</max_vel><min_depth>0.001</min_depth></ode></contact>
  <friction><ode><mu>1.13</mu><mu2>1.13</mu2></ode></friction><bounce/></surface></collision>%s</gazebo>"""


def surface(desc):
    s = desc.links["finger"].surface
    return (s.mu1, s.mu2, s.kp, s.kd, s.max_vel, s.min_depth, s.max_contacts)


def test_a_collision_block_gives_the_links_collisions_its_surface_and_contact_cap():
    desc = read_urdf("r", FINGER % (BLOCK % ""), lambda key, text: None)
    assert surface(desc) == (1.13, 1.13, 1e12, 1.0, 0.0, 0.001, 10)
    world = World()
    model = world.add_urdf("r", FINGER % (BLOCK % ""))
    assert len(model.links["finger"].collisions) == 2


def test_the_blocks_own_tags_apply_after_it_and_a_later_block_after_those():
    desc = read_urdf("r", FINGER % (BLOCK % "<mu1>0.5</mu1>"), lambda key, text: None)
    assert surface(desc)[:2] == (0.5, 1.13)
    later = FINGER % ((BLOCK % "") + '<gazebo reference="finger"><maxContacts>3</maxContacts></gazebo>')
    assert surface(read_urdf("r", later, lambda key, text: None))[6] == 3


def test_a_bad_value_in_the_block_names_the_link():
    bad = FINGER % (BLOCK % "").replace("<max_contacts>10", "<max_contacts>-1")
    with pytest.raises(ModelError) as e:
        read_urdf("r", bad, lambda key, text: None)
    assert "finger" in str(e.value) and "max_contacts" in str(e.value)
