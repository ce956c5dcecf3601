#!/usr/bin/env python3
"""rostest: KDL FK of modrob_kinematics.kdl_urdf equals robot_state_publisher's tf (world -> ee_link)."""
import random
import unittest

import numpy as np
import rospy
import rostest

from modrob_kinematics import kdl_urdf
from viz_test_utils import RobotDriver


def transform_matrix(t):
    import PyKDL
    r, p = t.transform.rotation, t.transform.translation
    return kdl_urdf.frame_to_matrix(PyKDL.Frame(PyKDL.Rotation.Quaternion(r.x, r.y, r.z, r.w),
                                                PyKDL.Vector(p.x, p.y, p.z)))


class KdlVersusTf(unittest.TestCase):
    def test_fk_matches_robot_state_publisher(self):
        chain = kdl_urdf.KinematicChain.from_urdf_string(rospy.get_param("/robot_description"))
        self.assertEqual(chain.tip_link, "ee_link")
        driver = RobotDriver("world", "ee_link")
        rng = random.Random(7)
        configs = [[0.0] * chain.n_joints] + [[rng.uniform(lo, hi) for lo, hi in zip(chain.lower,
                                                                                     chain.upper)]
                                              for _ in range(5)]
        for q in configs:
            t = driver.move(chain.joint_names, q)
            self.assertIsNotNone(t, "no tf world -> ee_link for q = %s" % q)
            np.testing.assert_allclose(transform_matrix(t), chain.fk_matrix(q), atol=1e-6,
                                       err_msg="KDL FK differs from tf at q = %s" % q)


if __name__ == "__main__":
    rospy.init_node("check_kdl_vs_tf")
    rostest.rosrun("modrob_viz", "check_kdl_vs_tf", KdlVersusTf)
