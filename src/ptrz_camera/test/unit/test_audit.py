"""ptrz_demo --audit's arithmetic on a synthetic tf history: a camera looking straight down at a
ball rolling at 1 m/s. An image whose ball is where tf says it was at the stamp audits clean; an
image drawn 0.1 s late is found to be 0.1 s late (the search the audit runs over tf's history)."""
import math

import numpy as np
import pytest
import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from scipy.spatial.transform import Rotation

from ptrz_camera import pinhole
from ptrz_camera.ros import audit

CAM = "ptrz2"
CAM_POS = np.array([0.0, 0.0, 3.0])
# camera link x forward looking down (a tilt of +90 degrees about y)
CAM_ROT = Rotation.from_euler("y", 90, degrees=True).as_matrix()
RADIUS = 0.11
SPEED = 1.0     # m/s along x


def ball_at(t):
    return np.array([-0.5 + SPEED * t, 0.2, RADIUS])


def transform(child, t, rot, pos):
    m = TransformStamped()
    m.header.frame_id = "world"
    m.header.stamp = rospy.Time.from_sec(t)
    m.child_frame_id = child
    m.transform.translation.x, m.transform.translation.y, m.transform.translation.z = pos
    q = Rotation.from_matrix(rot).as_quat()
    (m.transform.rotation.x, m.transform.rotation.y, m.transform.rotation.z,
     m.transform.rotation.w) = q
    return m


@pytest.fixture
def auditor():
    a = audit.ImageAudit.__new__(audit.ImageAudit)    # no subscriptions: tf is filled here
    a.ball_frame = "gazebo/ball/link"
    a.radius = RADIUS
    a.tf = tf2_ros.Buffer(cache_time=rospy.Duration(100.0), debug=False)   # no master
    optical = CAM_ROT.dot(audit.OPTICAL_TO_LINK)      # the renderer's optical frame
    for k in range(201):                               # 0 .. 2 s every 10 ms
        t = k * 0.01
        a.tf.set_transform(transform(a.optical_frame(CAM), t, optical, CAM_POS), "test")
        a.tf.set_transform(transform("%s_camera" % CAM, t, CAM_ROT, CAM_POS), "test")
        a.tf.set_transform(transform(a.ball_frame, t, np.eye(3), ball_at(t)), "test")
    return a


INTR = pinhole.intrinsics_from_fov(320, 240, 1.0)


def pixel(t):
    return pinhole.project(INTR, pinhole.to_camera((CAM_ROT, CAM_POS), ball_at(t)))


def test_rotation_helpers():
    q = Rotation.from_euler("xyz", [0.3, -0.2, 1.1]).as_quat()

    class Q(object):
        x, y, z, w = q
    r = audit.rotation(Q)
    assert r == pytest.approx(Rotation.from_quat(q).as_matrix(), abs=1e-12)
    assert audit.axis_angle(r, r) == pytest.approx(0.0, abs=1e-6)
    turned = r.dot(Rotation.from_euler("z", 0.05).as_matrix())
    assert audit.axis_angle(r, turned) == pytest.approx(0.05, abs=1e-9)
    # the optical frame (z forward, x right, y down) expressed in the link frame (x forward, y left)
    assert audit.OPTICAL_TO_LINK.dot([0, 0, 1]) == pytest.approx([1, 0, 0])
    assert audit.OPTICAL_TO_LINK.dot([1, 0, 0]) == pytest.approx([0, -1, 0])
    assert audit.OPTICAL_TO_LINK.dot([0, 1, 0]) == pytest.approx([0, 0, -1])


def test_the_drawn_pose_is_the_camera_link(auditor):
    rot, pos = auditor._drawn_pose(CAM, rospy.Time.from_sec(1.0))
    assert rot == pytest.approx(CAM_ROT, abs=1e-9)
    assert pos == pytest.approx(CAM_POS)


def test_an_image_drawn_at_its_stamp_fits_at_zero(auditor):
    u, v = pixel(1.0)
    cam_dt, ball_dt, err = auditor._fit_times(CAM, rospy.Time.from_sec(1.0), INTR, u, v)
    assert ball_dt == pytest.approx(0.0, abs=1e-9)
    assert err < 0.5


def test_an_image_drawn_late_is_found_late(auditor):
    u, v = pixel(1.0 - 0.1)       # the ball where it was 0.1 s before the stamp
    _, ball_dt, err = auditor._fit_times(CAM, rospy.Time.from_sec(1.0), INTR, u, v)
    assert ball_dt == pytest.approx(-0.1, abs=0.006)
    assert err < 0.5
    # 0.1 s at 1 m/s seen from 2.89 m: tens of pixels, so the search is not trivially at zero
    assert math.hypot(*(np.subtract(pixel(1.0), (u, v)))) > 10
