"""The world MarkerArray on a real physics World (no master): props only, in the world frame,
with their colours; re-sent only when something moved, was spawned or deleted."""
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
