"""Tier 1: EndEffectorSampler keeps quiet about a missing transform while its launch starts up
(robot_state_publisher has not published yet: a warning then alarms a user of a run that works)
and warns, naming the frames, once the transform is still missing after the grace period."""
import tf2_ros

from modrob_viz.ros import common


def test_a_missing_transform_is_warned_about_only_after_the_startup_grace(monkeypatch):
    class NoTf(object):            # tf2_ros.Buffer offers a service: it would need a ROS master
        def __init__(self, cache_time):
            pass

        def lookup_transform(self, *args):
            raise tf2_ros.LookupException("\"world\" passed to lookupTransform argument target_frame "
                                          "does not exist.")
    monkeypatch.setattr(common.tf2_ros, "Buffer", NoTf)
    monkeypatch.setattr(common.tf2_ros, "TransformListener", lambda buffer: None)
    warnings = []
    monkeypatch.setattr(common.rospy, "logwarn_throttle", lambda period, text: warnings.append(text))
    now = [100.0]
    sampler = common.EndEffectorSampler("world", "ee_link", clock=lambda: now[0])
    now[0] += sampler.STARTUP_GRACE - 0.1
    assert sampler.sample() is None and warnings == []
    now[0] += 0.2
    assert sampler.sample() is None
    assert len(warnings) == 1 and "world -> ee_link" in warnings[0]
