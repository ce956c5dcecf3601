"""The world MarkerArray on a real physics World (no master): props only, in the world frame,
with their colours, a world file's models of several links included; re-sent only when something
moved, was spawned or deleted."""
import os

import pytest
from visualization_msgs.msg import Marker

from modrob_sim.gazebo_ros.markers import WorldMarkers

FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sim")


def fixture(name):
    with open(os.path.join(FIXTURES, name)) as f:
        return f.read()


@pytest.fixture
def world():
    from modrob_sim.physics import World
    w = World(time_step=0.001)
    w.add_urdf("ground", fixture("ground.urdf"))
    w.add_urdf("box", fixture("box.urdf"), pose=((1.0, 2.0, 0.1), (0.0, 0.0, 0.0, 1.0)))
    w.add_urdf("arm2", fixture("arm2.urdf"), pose=((-1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)))
    return w


def test_props_only_with_pose_size_and_colour(world):
    arr = WorldMarkers(world).update(force=True)
    assert arr.markers[0].action == Marker.DELETEALL
    by_ns = {m.ns: m for m in arr.markers[1:]}
    assert set(by_ns) == {"ground", "box"}            # arm2 has joints: RobotModel draws it
    box = by_ns["box"]
    assert box.header.frame_id == "world" and box.type == Marker.CUBE
    assert (box.scale.x, box.scale.y, box.scale.z) == pytest.approx((0.2, 0.2, 0.2))
    assert (box.pose.position.x, box.pose.position.y) == pytest.approx((1.0, 2.0))
    assert (box.color.r, box.color.g, box.color.b) == pytest.approx((1.0, 0.5, 0.0))


def test_resent_only_on_change(world):
    wm = WorldMarkers(world)
    assert wm.update(force=True) is not None
    assert wm.update() is None                          # nothing moved
    world.models["box"].set_pose(((1.5, 2.0, 0.1), (0.0, 0.0, 0.0, 1.0)))
    moved = wm.update()
    assert moved is not None
    assert [m for m in moved.markers if m.ns == "box"][0].pose.position.x == pytest.approx(1.5)
    world.remove_model("box")
    gone = wm.update()
    assert gone is not None and not [m for m in gone.markers if m.ns == "box"]


def test_all_and_none(world):
    every = WorldMarkers(world, "all").update(force=True).markers[1:]
    assert {m.ns for m in every} == {"ground", "box", "arm2"}
    assert len(WorldMarkers(world, "none").update(force=True).markers) == 1
    with pytest.raises(ValueError):
        WorldMarkers(world, "some")


def test_a_world_files_model_of_several_links_is_a_prop(world):
    """A static SDF model of two links without joints between them (a lot's asphalt and a painted
    line) and a loose one of two links: their links are held by floating joints, nothing drives
    them and no robot_description covers them: both are drawn (the Polaris' parking lot and ramps
    were missing from RViz)."""
    world.add_sdf("""<sdf version='1.6'><world name='w'>
      <model name='lot'><static>true</static>
        <link name='asphalt'><pose>0 0 0.001 0 0 0</pose><visual name='v'><geometry><box>
          <size>4 3 0.002</size></box></geometry></visual></link>
        <link name='line'><pose>1 0 0.003 0 0 0</pose><visual name='v'><geometry><box>
          <size>0.1 2 0.002</size></box></geometry></visual></link></model>
      <model name='pair'><pose>3 0 0.5 0 0 0</pose>
        <link name='a'><collision name='c'><geometry><sphere><radius>0.1</radius></sphere></geometry>
          </collision><visual name='v'><geometry><sphere><radius>0.1</radius></sphere></geometry>
          </visual></link>
        <link name='b'><pose>0 0.5 0 0 0 0</pose><visual name='v'><geometry><sphere><radius>0.1</radius>
          </sphere></geometry></visual></link></model>
    </world></sdf>""")
    markers = WorldMarkers(world).update(force=True).markers[1:]
    assert {m.ns for m in markers} == {"ground", "box", "lot", "pair"}
    assert sorted((m.ns, round(m.pose.position.x, 3)) for m in markers if m.ns in ("lot", "pair")) == [
        ("lot", 0.0), ("lot", 1.0), ("pair", 3.0), ("pair", 3.0)]
