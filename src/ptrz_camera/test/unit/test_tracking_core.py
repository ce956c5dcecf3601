"""The tracking core against synthetic images from the pinhole model: the camera chain of the
seed's model, aiming, segmentation, floor positions, fusion, coverage, the scan plan, and the zoom
geometry (halving the field of view doubles the ball's image)."""
import math

import numpy as np
import pytest

from ptrz_camera import description, kinematics, pinhole, zoom
from ptrz_camera.tracking import coverage, localize, scan_plan, segment, synthetic

R = 0.11          # the ball's radius
W, H = 320, 128


@pytest.fixture(scope="module")
def chains():
    out = {"ptrz": kinematics.CameraChain(description.robot_description())}
    for ns, pose in description.load_camera_poses().items():
        out[ns] = kinematics.CameraChain(description.robot_description(ns, ns + "_", pose))
    return out


def test_forward_kinematics_is_the_seeds_geometry(chains):
    rot, t = chains["ptrz"].pose({})
    assert t == pytest.approx([0.75, 0.275, 3.675])
    assert rot == pytest.approx(np.eye(3))
    rot, t = chains["ptrz"].pose({"tilt": math.pi / 2})
    assert rot[:, 0] == pytest.approx([0, 0, -1], abs=1e-12)       # positive tilt looks down


@pytest.mark.parametrize("target", [(3.5, 0.0, R), (1.0, 1.8, R), (6.4, -1.9, R), (-2.0, 2.0, 0.0)])
def test_aim_puts_the_target_on_the_optical_axis(chains, target):
    chain = chains["ptrz"]
    for roll in (0.0, 0.7):
        pan, tilt = chain.aim(target, {"roll": roll})
        rot, t = chain.pose({"pan": pan, "tilt": tilt, "roll": roll})
        d = pinhole.to_camera((rot, t), target)
        assert d[0] > 0 and abs(d[1]) / d[0] < 1e-6 and abs(d[2]) / d[0] < 1e-6


def test_segmentation_finds_the_ball_and_nothing_else():
    intr = pinhole.intrinsics_from_fov(W, H, 1.0)
    chain = kinematics.CameraChain(description.robot_description())
    ball = (3.0, 0.3, R)
    pan, tilt = chain.aim(ball, {})
    pose = chain.pose({"pan": pan, "tilt": tilt})
    img = synthetic.render(pose, intr, ball, R, noise=0.007)
    det = segment.BallFinder().find(img)
    assert det is not None and det.area > 20
    assert det.u == pytest.approx(intr.cx, abs=1.0) and det.v == pytest.approx(intr.cy, abs=1.0)
    empty = synthetic.render(pose, intr, (30.0, 30.0, R), R)
    assert segment.BallFinder().find(empty) is None


@pytest.mark.parametrize("ball, offset", [((3.5, 0.0), (0.0, 0.0)), ((5.5, 1.5), (0.05, -0.03)),
                                          ((1.5, -1.8), (-0.08, 0.04)), ((6.3, -0.5), (0.0, 0.06))])
def test_one_camera_floor_position_within_2cm(chains, ball, offset):
    chain = chains["ptrz"]
    intr = pinhole.intrinsics_from_fov(W, H, zoom.NOMINAL_FOV)
    centre = (ball[0], ball[1], R)
    pan, tilt = chain.aim(centre, {})
    pose = chain.pose({"pan": pan + offset[0], "tilt": tilt + offset[1]})   # not perfectly centred
    det = segment.BallFinder().find(synthetic.render(pose, intr, centre, R))
    assert det is not None
    est = localize.floor_estimate(pose, intr, det.u, det.v, height=R)
    err = np.linalg.norm(est.xy - centre[:2])
    assert err < 0.02, "error %.3f m" % err


def test_three_cameras_fused_within_2cm_and_weighted(chains):
    intr = pinhole.intrinsics_from_fov(W, H, zoom.NOMINAL_FOV)
    centre = (4.2, -1.1, R)
    ests = []
    for ns in ("ptrz1", "ptrz2", "ptrz3"):
        chain = chains[ns]
        pan, tilt = chain.aim(centre, {})
        pose = chain.pose({"pan": pan + 0.03, "tilt": tilt - 0.02})
        det = segment.BallFinder().find(synthetic.render(pose, intr, centre, R, noise=0.01,
                                                         rng=np.random.default_rng(len(ests))))
        ests.append(localize.floor_estimate(pose, intr, det.u, det.v, height=R))
    fused = localize.fuse(ests)
    assert np.linalg.norm(fused.xy - centre[:2]) < 0.02
    assert np.trace(fused.cov) < min(np.trace(e.cov) for e in ests)
    assert localize.fuse([None]) is None


def test_ray_above_the_horizon_has_no_floor_point(chains):
    intr = pinhole.intrinsics_from_fov(W, H, 1.0)
    pose = chains["ptrz"].pose({"tilt": -0.3})        # looking up
    assert localize.floor_point(pose, intr, intr.cx, intr.cy) is None


def test_halving_the_field_of_view_doubles_the_ball_image():
    chain = kinematics.CameraChain(description.robot_description())
    ball = (4.0, 0.5, R)
    pan, tilt = chain.aim(ball, {})
    pose = chain.pose({"pan": pan, "tilt": tilt})
    sizes = []
    for fov in (0.4, 0.2):
        intr = pinhole.intrinsics_from_fov(640, 480, fov)
        mask = segment.BallFinder().mask(synthetic.render(pose, intr, ball, R))
        ys, xs = np.nonzero(mask)
        sizes.append(xs.max() - xs.min() + 1)
    assert sizes[1] / sizes[0] == pytest.approx(2.0, rel=0.05)


def test_zoom_range_and_units():
    assert zoom.check_fov(1.0) == 1.0
    for bad in (0.01, 3.0, float("nan"), "wide"):
        with pytest.raises(Exception, match="zoom"):
            zoom.check_fov(bad)
    assert zoom.zoom_factor(zoom.TELE_FOV) == pytest.approx(zoom.MAX_ZOOM)
    assert zoom.fov_for_zoom(1.0) == pytest.approx(zoom.NOMINAL_FOV)
    assert zoom.focal_length_px(math.pi / 2, 640) == pytest.approx(320.0)


def test_coverage_marks_the_footprint_and_ages():
    chain = kinematics.CameraChain(description.robot_description())
    intr = pinhole.intrinsics_from_fov(W, H, zoom.NOMINAL_FOV)
    grid = coverage.CoverageGrid(0.5, -2.0, 6.0, 4.0, resolution=0.1, stale_time=10.0)
    pan, tilt = chain.aim((3.5, 0.0, 0.0), {})
    poly = coverage.footprint(chain.pose({"pan": pan, "tilt": tilt}), intr)
    grid.mark(poly, t=5.0)
    v = grid.values(5.0)
    assert v.shape == (40, 60)
    centre = v[20, 30]
    assert centre == 0
    assert (v == -1).any()                     # not all of the field in one view
    assert grid.values(10.0)[20, 30] == 50
    assert grid.values(100.0)[20, 30] == 100
    assert 0.05 < grid.fraction_seen(5.0) < 1.0


def test_scan_plan_gives_each_camera_the_nearest_strip():
    cams = [(0.0, 0.0), (7.0, 0.0), (3.5, -3.5)]
    plan = scan_plan.ScanPlan(cams, (0.5, -2.0, 6.0, 4.0), dwell=1.0)
    xs = [r[0] + r[2] / 2 for r in plan.rects]
    assert xs[0] < xs[2] < xs[1]                # ends to the end cameras, middle to the side camera
    for pts, r in zip(plan.points, plan.rects):
        for x, y, _ in pts:
            assert r[0] <= x <= r[0] + r[2] and r[1] <= y <= r[1] + r[3]
    first = plan.target(0, 0.0, settled=True)
    assert plan.target(0, 0.5, settled=True) == first
    assert plan.target(0, 1.1, settled=True) != first
