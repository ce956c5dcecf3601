#!/usr/bin/env python3
"""rostest node of tracking.test: tracking.launch (indoor world, rendered images, the ball on its
figure eight): the network's /ptrz_network/ball (PointStamped) against the ball's true position
(the simulator's: its link pose stamped on tf, at the estimate's time; the /gazebo/model_states
poses must lie on that path: recorder.py says why not their time of arrival) over ~duration s of
simulated time: at least a share ~within of the estimates within ~tolerance (the issue's 5 cm),
the mean error at most ~mean_error,
none farther than ~max_error, the ball in the central third of the tracking camera's image in at
least a share ~centred of the detections, and estimates all along the run: for a share
~published of the image times with a detection (the network withholds the estimates it cannot
trust)."""
import time
import unittest

import rospy
import rostest

from modrob_sim.waits import wait_until
from ptrz_camera.ros.recorder import TrackingRecorder
from ptrz_camera.tracking import evaluate


class Tracking(unittest.TestCase):
    def test_the_network_locates_the_ball(self):
        cams = rospy.get_param("~cameras", "ptrz").split()
        duration = float(rospy.get_param("~duration", 12.0))
        tolerance = float(rospy.get_param("~tolerance", 0.05))
        rec = TrackingRecorder(cams)
        wait_until(lambda: rec.snapshot()[1], 120.0, "a first estimate on /ptrz_network/ball")
        t0 = rospy.get_time()
        end = time.monotonic() + 150.0
        while rospy.get_time() - t0 < duration and time.monotonic() < end and not rospy.is_shutdown():
            rospy.rostime.wallsleep(0.2)
        truth, est, _per_cam, pixels, images, states = rec.snapshot()
        truth = [p for p in truth if p[0] >= t0 - 1.0]
        states = [p for p in states if p[0] >= t0]
        est = [p for p in est if p[0] >= t0]
        pix = [p for ps in pixels.values() for p in ps]
        img = images[cams[0]]
        centred = evaluate.centred_fraction(pix, img.shape[1], img.shape[0])
        s = evaluate.summarize(truth, est, tolerance, centred)
        off = evaluate.off_path(states, truth)
        rospy.loginfo("tracking over %.1f s simulated: %d estimates, error mean %.1f cm, max %.1f cm, "
                      "%.0f %% within %.0f cm; ball in the central third in %.0f %% of %d detections",
                      rospy.get_time() - t0, s.n, 100 * s.mean, 100 * s.max, 100 * s.within,
                      100 * tolerance, 100 * s.centred, len(pix))
        rospy.loginfo("/gazebo/model_states: %d poses, at most %.1f mm from the stamped path (tf)",
                      len(off), 1000 * (off.max() if len(off) else float("nan")))
        self.assertGreaterEqual(rospy.get_time() - t0, 0.95 * duration, "the simulation did not run")
        self.assertGreater(len(off), 5 * duration, "too few /gazebo/model_states poses of the ball")
        self.assertLess(off.max(), 0.01, "the ball's model_states poses are not on its tf path: "
                        "the truth is not the simulator's")
        self.assertGreaterEqual(s.n, 2 * duration, "too few estimates: %d in %.0f s" % (s.n, duration))
        self.assertGreaterEqual(s.duration, 0.8 * duration, "estimates stopped before the end")
        t1 = max([p[0] for p in est] or [t0])
        cover = evaluate.coverage([p[0] for p in est], t0, rospy.get_time())
        share = evaluate.published_share([p[0] for p in est], rec.detection_times(), t0, t1)
        rospy.loginfo("estimates for %.0f %% of the image times with a detection, %.1f per simulated s, "
                      "one at most 0.5 s old during %.0f %% of the time", 100 * share,
                      len(est) / max(1e-6, rospy.get_time() - t0), 100 * cover)
        self.assertGreaterEqual(share, float(rospy.get_param("~published", 0.9)),
                                "estimates for only %.0f %% of the image times with a detection"
                                % (100 * share))
        self.assertGreaterEqual(s.within, float(rospy.get_param("~within", 0.9)),
                                "only %.0f %% of the estimates within %.0f cm of the ball (mean %.1f cm)"
                                % (100 * s.within, 100 * tolerance, 100 * s.mean))
        self.assertLessEqual(s.mean, float(rospy.get_param("~mean_error", 0.04)),
                             "mean error %.1f cm" % (100 * s.mean))
        self.assertLessEqual(s.max, float(rospy.get_param("~max_error", 0.25)),
                             "an estimate %.1f cm from the ball" % (100 * s.max))
        self.assertGreaterEqual(s.centred, float(rospy.get_param("~centred", 0.9)),
                                "the ball left the central third of the image")


if __name__ == "__main__":
    rospy.init_node("tracking_check")
    rostest.rosrun("ptrz_camera", "tracking", Tracking)
