"""The network's logic end to end on synthetic pinhole images (no renderer, no ROS): three
cameras whose joints follow their commands find, follow and locate the ball on its figure eight,
then scan and cover the floor when it is gone."""
import numpy as np
import pytest

from ptrz_camera import description, kinematics, pinhole
from ptrz_camera.tracking import network, paths, synthetic
from ptrz_camera.worlds import FIELD

R = 0.11
FLOOR = (FIELD.centre_x - FIELD.length / 2, FIELD.centre_y - FIELD.width / 2, FIELD.length, FIELD.width)


@pytest.fixture(scope="module")
def chains():
    poses = description.load_camera_poses()
    return {ns: kinematics.CameraChain(description.robot_description(ns, ns + "_", poses[ns]))
            for ns in ("ptrz1", "ptrz2", "ptrz3")}


def simulate(net, chains, ball_at, t_end, dt=0.1):
    """Cameras move to their commands in one step (ideal heads); returns (t, truth, estimate)."""
    intr = pinhole.intrinsics_from_fov(240, 96, 1.3962634)
    q = {ns: {"pan": 0.0, "tilt": 0.6, "roll": 0.0} for ns in chains}
    out = []
    t = 0.0
    while t < t_end:
        ball = ball_at(t)
        for ns, chain in chains.items():
            net.on_joints(ns, t, q[ns])
            centre = (ball[0], ball[1], R) if ball is not None else (100.0, 100.0, R)
            pose = chain.pose(q[ns])
            # the pose given (as the node takes it from tf) or from the joints (ptrz1)
            net.on_image(ns, t, synthetic.render(pose, intr, centre, R), intr,
                         None if ns == "ptrz1" else pose)
        fused = net.fuse(t)
        if fused is not None and ball is not None:
            out.append((t, ball, fused[1].xy))
        settled = {ns: True for ns in chains}
        for ns, (pan, tilt) in net.commands(t, settled).items():
            q[ns] = {"pan": pan, "tilt": tilt, "roll": 0.0}
        t += dt
    return out


def test_the_network_follows_and_locates_the_ball(chains):
    path = paths.FigureEight(period=30.0)
    net = network.Network(chains, FLOOR, R, lead=0.1)
    out = simulate(net, chains, path.position, 8.0)
    assert net.mode == "tracking"
    late = [np.linalg.norm(np.asarray(b) - e) for t, b, e in out if t > 1.0]
    assert len(late) > 50
    assert max(late) < 0.03, "max error %.3f m" % max(late)


def test_scanning_covers_the_floor_when_nothing_is_seen(chains):
    net = network.Network(chains, FLOOR, R, lost_time=1.0)
    simulate(net, chains, lambda t: None, 30.0, dt=0.25)
    assert net.mode == "scanning"
    assert net.grid.fraction_seen(30.0) > 0.9
    values = net.grid.values(30.0)
    assert values.min() <= 2 and (values >= 0).all()      # the last image was 0.25 s before


def test_a_partly_hidden_ball_gives_no_floor_estimate(chains):
    """The centroid of the visible part of a ball is not the image of its centre: a blob much
    smaller than a whole ball at that range (a robot hides the rest) yields a detection, no
    estimate; the whole ball an estimate within 2 cm."""
    intr = pinhole.intrinsics_from_fov(320, 128, 1.3962634)
    chain = chains["ptrz2"]
    centre = (4.0, 0.5, R)
    pan, tilt = chain.aim(centre, {})
    pose = chain.pose({"pan": pan, "tilt": tilt, "roll": 0.0})
    img = synthetic.render(pose, intr, centre, R)
    net = network.Network(chains, FLOOR, R)
    whole = net.on_image("ptrz2", 0.0, img, intr, pose)
    assert whole.estimate is not None
    assert np.linalg.norm(whole.estimate.xy - centre[:2]) < 0.02
    u = int(whole.detection.u)
    for hide in (slice(u, None), slice(None, u + 1)):   # a grey robot hides most of it, either side
        part = img.copy()
        part[:, hide] = (90, 90, 90)
        obs = network.Network(chains, FLOOR, R).on_image("ptrz2", 0.0, part, intr, pose)
        assert obs.detection is not None and obs.detection.area < 0.7 * whole.detection.area
        assert obs.estimate is None, "an estimate from a partly hidden ball: %s" % (obs.estimate.xy,)


def test_off_path_measures_the_distance_to_the_stamped_path():
    from ptrz_camera.tracking import evaluate
    path = [(0.1 * i, 0.1 * i, 0.0) for i in range(30)]            # along x at 1 m/s
    # model_states kept with a late time of arrival: still on the path
    assert evaluate.off_path([(1.0, 0.7, 0.0), (2.0, 1.55, 0.0)], path) == pytest.approx([0.0, 0.0])
    assert evaluate.off_path([(1.0, 1.0, 0.03)], path) == pytest.approx([0.03])
    # far from any sample within the window around its time
    assert evaluate.off_path([(0.5, 2.5, 0.0)], path, window=0.5)[0] == pytest.approx(1.5)
    assert len(evaluate.off_path([(9.0, 0.0, 0.0)], path)) == 0


def _located(chains, ns, centre, intr, t, net):
    chain = chains[ns]
    pan, tilt = chain.aim(centre, {})
    pose = chain.pose({"pan": pan, "tilt": tilt, "roll": 0.0})
    return net.on_image(ns, t, synthetic.render(pose, intr, centre, R), intr, pose)


def test_one_estimate_per_image_time_from_that_time_only(chains):
    """The cameras' images of one time are fused together once all are in, never with another
    time's; none is published before a camera has locked on (three images in a row)."""
    intr = pinhole.intrinsics_from_fov(320, 128, 1.3962634)
    net = network.Network(chains, FLOOR, R)
    out = []
    for k in range(4):
        t = 0.1 * k
        centre = (3.0 + 0.5 * k, 0.5, R)          # 5 m/s: any mixing of times would show
        for ns in ("ptrz1", "ptrz2"):
            _located(chains, ns, centre, intr, t, net)
            out += [(t, centre, e) for t, e, _src in net.fuse_ready()]   # ptrz3 not in: waits
        _located(chains, "ptrz3", centre, intr, t, net)
        out += [(t_, centre, e) for t_, e, _src in net.fuse_ready()]
    assert [round(t, 3) for t, _c, _e in out] == [0.2, 0.3]
    for _t, centre, e in out:
        assert np.linalg.norm(e.xy - centre[:2]) < 0.02
    assert net.counts["rejected_not_locked"] == 2 and net.counts["published"] == 2


def test_rays_that_disagree_give_no_estimate(chains):
    intr = pinhole.intrinsics_from_fov(320, 128, 1.3962634)
    net = network.Network(chains, FLOOR, R, min_streak=1)
    _located(chains, "ptrz1", (3.0, 0.5, R), intr, 0.0, net)
    _located(chains, "ptrz2", (3.4, 0.5, R), intr, 0.0, net)    # sees another ball, 40 cm off
    _located(chains, "ptrz3", (3.0, 0.9, R), intr, 0.0, net)    # and another
    assert net.fuse_ready() == []
    assert net.counts["rejected_residual"] == 1
    # two agree, the third is off: it is left out
    _located(chains, "ptrz1", (3.0, 0.5, R), intr, 0.1, net)
    _located(chains, "ptrz2", (3.0, 0.5, R), intr, 0.1, net)
    _located(chains, "ptrz3", (3.0, 1.0, R), intr, 0.1, net)
    (t, est, src), = net.fuse_ready()
    assert sorted(n for n, _o in src) == ["ptrz1", "ptrz2"]
    assert np.linalg.norm(est.xy - (3.0, 0.5)) < 0.02


def test_cubic_joint_interpolation_with_velocities():
    cam = network.Camera("c", None)
    for t in (0.0, 0.02, 0.04):                  # constant acceleration 100 rad/s^2
        cam.add_joints(t, {"pan": 50.0 * t * t}, {"pan": 100.0 * t})
    assert cam.joints_at(0.013)["pan"] == pytest.approx(50.0 * 0.013 ** 2, abs=1e-9)
    assert cam.joints_at(0.05, max_gap=0.05) is None            # not between two samples
    assert cam.joints_at(0.05)["pan"] == pytest.approx(50.0 * 0.04 ** 2)
