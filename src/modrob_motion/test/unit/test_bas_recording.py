"""The joints plot of a Bulbs and Slides run breaks its lines where nothing was recorded (the
scenario samples only while a robot moves, settles or grips), instead of drawing a straight line
across a wait that looks like a joint standing still while its command moves."""
import math

import numpy as np

from modrob_motion.bulbs_and_slides.recording import Recorder


class FakeArm(object):
    class info(object):
        robot_id = 0
        arm_joints = ["j1"]
        gripper = None

    def __init__(self):
        self.q = 0.0

    def measured(self, names):
        return np.array([self.q])

    def commanded(self, names):
        return np.array([self.q + 0.01])

    def efforts(self, names):
        return np.array([])


def record(times):
    now = [0.0]
    rec = Recorder({0: lambda q: (float(q[0]), 0.0, 0.0)}, period=0.02, clock=lambda: now[0])
    arm = FakeArm()
    for t in times:
        now[0] = t
        arm.q = t
        rec.sample(arm)
    return rec


def test_a_row_of_nan_at_each_gap():
    rec = record([0.0, 0.025, 0.05, 10.0, 10.03, 30.0])
    t, cmd, meas, _, _ = rec.arrays(0)
    bt, bcmd, bmeas, gaps = rec.broken_at_gaps(t, cmd, meas)
    assert gaps == [(0.05, 10.0), (10.03, 30.0)]
    assert len(bt) == len(t) + 2
    assert [i for i, v in enumerate(bt) if math.isnan(v)] == [3, 6]
    assert np.isnan(bcmd[3]).all() and np.isnan(bmeas[6]).all()
    assert np.allclose(bt[~np.isnan(bt)], t)
    assert np.allclose(bmeas[~np.isnan(bt)], meas)


def test_no_gap_no_change():
    rec = record([0.0, 0.02, 0.04, 0.3])
    t, cmd, meas, _, _ = rec.arrays(0)
    bt, bcmd, bmeas, gaps = rec.broken_at_gaps(t, cmd, meas)
    assert gaps == [] and np.array_equal(bt, t) and np.array_equal(bmeas, meas)


def test_plot_with_gaps(tmp_path):
    rec = record([0.0, 0.02, 0.04, 10.0, 10.02])
    out = rec.plot_joints(str(tmp_path / "joints.png"), {0: ["j1"]})
    with open(out, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
