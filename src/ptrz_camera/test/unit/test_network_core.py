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
