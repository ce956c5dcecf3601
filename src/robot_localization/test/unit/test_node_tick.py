"""EkfNode's periodic tick without a ROS master: an estimate goes out once per stamp, also when
the node's clock is behind the measurements' stamps, and again after the clock went back."""
import collections
import threading

import numpy as np
import pytest

from robot_localization import config, ekf, node
from robot_localization.measurements import twist_measurement

# Jackal's robot_localization.yaml, its wheel odometry only
JACKAL_LIKE = {"frequency": 50, "two_d_mode": True, "predict_to_current_time": True, "odom0": "odom",
               "odom0_config": [False] * 6 + [True, True, True, False, False, True] + [False] * 3}


@pytest.fixture
def tick(monkeypatch):
    """(enqueue(t), tick(now) -> stamps published so far) on an EkfNode whose ROS parts are left out."""
    cfg = config.read(lambda name, default: JACKAL_LIKE.get(name, default))
    n = object.__new__(node.EkfNode)
    n.cfg = cfg
    n.filter = ekf.Ekf(cfg.process_noise, cfg.initial_covariance, cfg.two_d_mode)
    n.lock = threading.Lock()
    n.queue = collections.deque()
    n.last_measurement = None
    n.last_stamp = None
    n.last_tick = None
    n.latest = {}
    n._warned = {}
    published = []
    n._publish = lambda state, cov, stamp: published.append(round(stamp.to_sec(), 6))
    clock = [0.0]
    monkeypatch.setattr(node.rospy, "get_time", lambda: clock[0])

    def enqueue(t):
        values, cov, mask = twist_measurement(cfg.inputs[0].config, (0.5, 0.0, 0.0), (0.0, 0.0, 0.0),
                                              np.eye(6) * 0.001)
        n.enqueue("odom0", t, [ekf.Measurement(values, cov, mask, t)])

    def run(now):
        clock[0] = now
        n._tick(None)
        return list(published)
    return enqueue, run


def test_a_clock_behind_the_measurements_publishes_each_stamp_once(tick):
    enqueue, run = tick
    enqueue(12.121)
    assert run(12.100) == [12.121]          # the newest measurement's time: the clock is behind it
    assert run(12.110) == [12.121]          # nothing newer: no second message with that stamp
    assert run(12.120) == [12.121]
    assert run(12.140) == [12.121, 12.14]   # the clock passed it: predicted to the tick's time
    assert run(12.140) == [12.121, 12.14]   # simulated time stood still


def test_after_the_clock_went_back_the_tick_publishes_again(tick):
    enqueue, run = tick
    enqueue(20.0)
    assert run(20.02) == [20.02]
    assert len(run(0.52)) == 2       # reset_simulation: not silent until the clock is back at 20.02
    assert len(run(0.54)) == 2       # ... once; then again only what is newer
