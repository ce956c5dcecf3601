"""The demo motion sources stay within joint limits; IK path following ends on the path's end."""
import os

import numpy as np

from modrob_kinematics import kdl_urdf
from modrob_viz import paths, samples

FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")


def chain():
    with open(os.path.join(FIXTURES, "planar_limited.urdf")) as f:
        return kdl_urdf.KinematicChain.from_urdf_string(f.read())


def test_sample_trajectory_and_wave_respect_limits():
    c = chain()
    limits = dict(zip(c.joint_names, zip(c.lower, c.upper)))
    path = samples.sample_joint_trajectory(c.joint_names, limits, 3700)
    assert path.positions.shape == (3700, 2)
    assert np.all(path.positions >= np.array(c.lower) - 1e-12)
    assert np.all(path.positions <= np.array(c.upper) + 1e-12)
    assert path.times[-1] > 0
    for t in np.linspace(0, 20, 50):
        assert c.within_limits(samples.joint_wave(c.joint_names, limits, t))


def test_follow_path_ik_ends_on_the_goal():
    c = chain()
    pts = paths.line((0.3, 0.1, 0.0), (0.2, 0.3, 0.0), n=20)
    qs = samples.follow_path_ik(c, pts, wobble=0.0)
    assert len(qs) == 20
    np.testing.assert_allclose(c.fk_position(qs[-1]), pts[-1], atol=1e-4)
