"""The node's ~world_markers (StatePublishers.publish_markers): nothing is built while nobody
subscribes, and a subscriber gets the world as it is at the next marker time."""
import os

import rospy

from modrob_sim.gazebo_ros import state_publishers
from modrob_sim.gazebo_ros.node_params import Params
from modrob_sim.physics import World

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "physics")


class FakePublisher(object):
    def __init__(self, topic, msg_class, queue_size=1, latch=False, **kw):
        self.topic, self.sent, self.connections = topic, [], 0

    def get_num_connections(self):
        return self.connections

    def publish(self, msg):
        self.sent.append(msg)

    def unregister(self):
        pass


def _publishers(monkeypatch):
    monkeypatch.setattr(rospy, "Publisher", FakePublisher)
    monkeypatch.setattr(state_publishers, "publisher", FakePublisher)
    world = World()
    with open(os.path.join(FIX, "box.urdf")) as f:
        box = world.add_urdf("box", f.read(), pose=((0.0, 0.0, 0.5), (0.0, 0.0, 0.0, 1.0)))
    return world, box, state_publishers.StatePublishers(world, Params())


def _built(monkeypatch, sp):
    calls = []
    update = sp._markers.update

    def counting(force=False):
        calls.append(force)
        return update(force=force)
    monkeypatch.setattr(sp._markers, "update", counting)
    return calls


def test_no_marker_array_is_built_without_subscribers(monkeypatch):
    world, box, sp = _publishers(monkeypatch)
    built = _built(monkeypatch, sp)
    for _ in range(300):                    # the box falls: it moves at every marker time
        world.step(1)
        sp.after_step()
    assert built == [] and sp._marker_pub.sent == []


def test_a_subscriber_gets_the_world_as_it_is_at_the_next_marker_time(monkeypatch):
    world, box, sp = _publishers(monkeypatch)
    sp.publish_markers(force=True)          # as after a reset: the latched array
    z0 = sp._marker_pub.sent[-1].markers[1].pose.position.z
    for _ in range(200):
        world.step(1)
        sp.after_step()
    assert len(sp._marker_pub.sent) == 1
    sp._marker_pub.connections = 1
    for _ in range(100):
        world.step(1)
        sp.after_step()
    assert len(sp._marker_pub.sent) >= 2
    z = sp._marker_pub.sent[1].markers[1].pose.position.z
    assert z < z0 - 0.05 and abs(z - box.pose[0][2]) < 0.05


def test_a_pause_brings_the_latched_markers_up_to_date(monkeypatch):
    # a subscriber that comes while the simulation is paused gets the latched array at once
    world, box, sp = _publishers(monkeypatch)
    sp.on_pause()
    assert sp._marker_pub.sent == []        # nothing was skipped: nothing to do
    for _ in range(300):
        world.step(1)
        sp.after_step()
    assert sp._marker_pub.sent == []
    sp.on_pause()
    assert len(sp._marker_pub.sent) == 1
    z = sp._marker_pub.sent[0].markers[1].pose.position.z
    assert abs(z - box.pose[0][2]) < 1e-9
    sp.on_pause()                           # up to date: not sent again
    assert len(sp._marker_pub.sent) == 1
