"""The scenario's joint trajectories as sent to a JointTrajectoryController: points with the
smoothstep's velocities, from the start to the end, whose cubic (Hermite) interpolation stays on the
streamed path."""
import numpy as np
import pytest

from modrob_motion.bulbs_and_slides.trajectory import JointTrajectory, time_waypoints


def _traj():
    return time_waypoints(["a", "b"], [[0.0, 1.0], [0.5, 0.8], [0.2, 0.8]], 0.5)


def test_velocity_is_the_derivative_of_sample():
    tr = _traj()
    h = 1e-6
    for t in np.linspace(0.01, tr.duration - 0.01, 37):
        fd = (tr.sample(t + h) - tr.sample(t - h)) / (2 * h)
        assert np.allclose(tr.velocity(t), fd, atol=1e-5), t
    assert np.allclose(tr.velocity(tr.t[1]), 0.0, atol=1e-9)     # rest at every waypoint
    assert not np.any(tr.velocity(-1.0)) and not np.any(tr.velocity(tr.duration + 1.0))


def test_samples_cover_the_trajectory_and_end_on_its_last_waypoint():
    tr = _traj()
    pts = tr.samples(0.01)
    times = [p[0] for p in pts]
    assert times[0] == pytest.approx(0.0) and times[-1] == pytest.approx(tr.duration)
    assert all(b > a for a, b in zip(times, times[1:])), "times must increase strictly"
    assert np.allclose(pts[-1][1], [0.2, 0.8]) and np.allclose(pts[-1][2], 0.0)
    assert max(np.diff(times)) <= 0.01 + 1e-12


def test_cubic_between_samples_follows_the_path():
    tr = _traj()
    pts = tr.samples(0.01)
    worst = 0.0
    for (t0, q0, v0), (t1, q1, v1) in zip(pts, pts[1:]):
        h = t1 - t0
        for u in (0.25, 0.5, 0.75):
            h00, h10 = 2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u
            h01, h11 = -2 * u ** 3 + 3 * u ** 2, u ** 3 - u ** 2
            q = h00 * q0 + h10 * h * v0 + h01 * q1 + h11 * h * v1
            worst = max(worst, float(np.max(np.abs(q - tr.sample(t0 + u * h)))))
    assert worst < 1e-5


def test_a_single_waypoint_gives_one_point():
    tr = JointTrajectory(["a"], [[0.3]], [0.0])
    pts = tr.samples(0.01)
    assert len(pts) == 1
    assert np.allclose(pts[-1][1], [0.3])
