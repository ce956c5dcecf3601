"""``can_stacker`` node: find two cans (from the laser detections or the simulator's model
states), pick the farther one, stand it on the nearer one, judge the stack, print a RESULT line.

Parameters (~): source (detection | model_states, default detection), result_file (YAML with
the outcome), plot_dir (the scan-and-detections PNG and the joint tracking PNG go there), wait (s,
how long to wait for the arm and the detections, default 120), jitter (m: before starting, move
every can by a random offset in +-jitter in x and y; default 0), seed (of that jitter, default 0),
approach, clearance, grip_effort, cart_speed (the planner's).
"""
import math
import os
import random
import time

import rospy
import tf2_ros
from gazebo_msgs.msg import ModelState
from gazebo_msgs.srv import SetModelState
from geometry_msgs.msg import PoseArray
from sensor_msgs.msg import LaserScan

from katana_sim.detection import detect
from katana_sim.errors import KatanaError
from katana_sim.planner import Can, StackPlanner
from katana_sim.tf_util import apply_transform
from katana_sim.stacker import ArmInterface, Stacker, StackError
from modrob_sim import waits
from modrob_sim.end_launch import finish_scenario

BASE_FRAME = "katana_base_link"
CAN_HEIGHT = 0.122
CAN_RADIUS = 0.033


def _lookup(buffer, target, source, wait):
    """The latest transform, waiting up to ``wait`` wall seconds (tf2's own timeout is simulated
    time: at real_time_factor 0 its 120 s are gone in a few wall seconds)."""
    try:
        return waits.lookup_transform(buffer, target, source, wait)
    except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException) as exc:
        raise StackError("no transform %s -> %s after %.0f s (is robot_state_publisher running?): %s"
                         % (source, target, wait, exc))


class CanStackNode(object):
    def __init__(self):
        self.source = rospy.get_param("~source", "detection")
        if self.source not in ("detection", "model_states"):
            raise StackError("~source must be 'detection' or 'model_states', got %r" % self.source)
        self.wait = float(rospy.get_param("~wait", 120.0))
        self.result_file = rospy.get_param("~result_file", "")
        self.plot_dir = rospy.get_param("~plot_dir", "")
        self.jitter = float(rospy.get_param("~jitter", 0.0))
        self.seed = int(rospy.get_param("~seed", 0))
        self.planner = StackPlanner(approach=rospy.get_param("~approach", 0.07),
                                    clearance=rospy.get_param("~clearance", 0.04),
                                    grip_effort=rospy.get_param("~grip_effort", 0.5),
                                    cart_speed=rospy.get_param("~cart_speed", 0.05))
        self.tf_buffer = tf2_ros.Buffer()
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        progress("waiting for the arm (katana.launch)")
        self.arm = ArmInterface(wait=self.wait)
        self.stacker = Stacker(self.arm, self.planner, log=progress)

    # -- where are the cans ----------------------------------------------------------------------
    def can_poses(self):
        """{name: pose} of the simulator's models with 'can' in the name, once there are two (or
        after ``wait`` wall seconds: what there is)."""
        cans = {}

        def two():
            cans.clear()
            cans.update((n, p) for n, p in self.arm.model_poses().items() if "can" in n)
            return len(cans) >= 2
        waits.wait_until(two, self.wait)
        return cans

    def jitter_cans(self):
        """Move every can by a seeded random offset (benchmarks); returns the offsets."""
        rng = random.Random(self.seed)
        set_state = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)
        set_state.wait_for_service(self.wait)
        moved = {}
        for name, (p, _) in sorted(self.can_poses().items()):
            dx, dy = rng.uniform(-self.jitter, self.jitter), rng.uniform(-self.jitter, self.jitter)
            st = ModelState(model_name=name, reference_frame="world")
            st.pose.position.x, st.pose.position.y, st.pose.position.z = p[0] + dx, p[1] + dy, p[2]
            st.pose.orientation.w = 1.0
            res = set_state(st)
            if not res.success:
                raise StackError("could not move %s: %s" % (name, res.status_message))
            moved[name] = (dx, dy)
        text = ", ".join("%s %+.1f/%+.1f mm" % (n, dx * 1000, dy * 1000)
                         for n, (dx, dy) in sorted(moved.items()))
        progress("jitter (seed %d): %s" % (self.seed, text))
        rospy.sleep(0.5)
        return moved

    def cans_from_model_states(self):
        poses = self.can_poses()
        if len(poses) < 2:
            raise StackError("the simulator reports %d models with 'can' in the name (%s); two are needed"
                             % (len(poses), ", ".join(sorted(poses))))
        tf = _lookup(self.tf_buffer, BASE_FRAME, "world", self.wait)
        cans = []
        for n in sorted(poses):
            (p, _) = poses[n]
            c = apply_transform(tf, p)
            cans.append(Can(c[0], c[1], c[2] - 0.5 * CAN_HEIGHT, CAN_RADIUS, CAN_HEIGHT))
        return cans

    def cans_from_detection(self):
        progress("waiting for /katana/detected_objects (the laser detector)")
        msg = None
        start = rospy.get_time()
        end = time.monotonic() + self.wait      # wall seconds, as every wait of this node
        while not rospy.is_shutdown() and time.monotonic() < end:
            try:
                msg = rospy.wait_for_message("/katana/detected_objects", PoseArray, timeout=5.0)
            except rospy.ROSException:
                continue
            if len(msg.poses) >= 2 and msg.header.stamp.to_sec() > start:
                break
        if msg is None or len(msg.poses) < 2:
            raise StackError("the detector found %d objects within %.0f s; two cans are needed"
                             % (0 if msg is None else len(msg.poses), self.wait))
        tf = _lookup(self.tf_buffer, BASE_FRAME, msg.header.frame_id, self.wait)
        cans = []
        for pose in msg.poses:
            c = apply_transform(tf, (pose.position.x, pose.position.y, pose.position.z))
            # the cans stand on the table the arm stands on: the base's foot plane
            cans.append(Can(c[0], c[1], 0.0, CAN_RADIUS, CAN_HEIGHT))
        return cans

    def model_near(self, can, poses):
        """The simulator's can model nearest to a can (for judging the result), of ``poses``
        (:meth:`can_poses`)."""
        if not poses:
            raise StackError("/gazebo/model_states named no model with 'can' in its name within %.0f s "
                             "(is the simulator running?)" % self.wait)
        tf = _lookup(self.tf_buffer, BASE_FRAME, "world", self.wait)
        best, dist = None, float("inf")
        for name, (p, _) in sorted(poses.items()):
            c = apply_transform(tf, p)
            d = math.hypot(c[0] - can.x, c[1] - can.y)
            if d < dist:
                best, dist = name, d
        return best, dist

    def save_scan_figure(self):
        """The laser scan with the detector's result (the same pure function) as a PNG."""
        from katana_sim.plots import plot_scan
        scan = rospy.wait_for_message("/scan", LaserScan, timeout=self.wait)
        found = detect(scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max,
                       radius=0.033)
        angles = [scan.angle_min + i * scan.angle_increment for i in range(len(scan.ranges))]
        os.makedirs(self.plot_dir, exist_ok=True)
        path = plot_scan(angles, scan.ranges, scan.range_min, scan.range_max, found,
                         os.path.join(self.plot_dir, "katana_scan_detections.png"),
                         title="Katana laser scan (%s) and %d detected objects"
                         % (scan.header.frame_id, len(found)))
        progress("scan and detections: %s" % path)

    def run(self):
        if self.jitter > 0:
            self.jitter_cans()
        if self.plot_dir and self.source == "detection":
            self.save_scan_figure()
        cans = self.cans_from_detection() if self.source == "detection" else self.cans_from_model_states()
        cans.sort(key=lambda c: -math.hypot(c.x, c.y))
        top, bottom = cans[0], cans[1]
        poses = self.can_poses()
        top_name, top_err = self.model_near(top, poses)
        bottom_name, bottom_err = self.model_near(bottom, poses)
        # the frames are known (static ones): the arm's moving frames need not come in any more
        self.tf_listener.unregister()
        progress("cans (%s): pick the farther at (%.3f, %.3f) [%s, %.1f mm off], stack it on the nearer at "
                 "(%.3f, %.3f) [%s, %.1f mm off]"
                 % (self.source, top.x, top.y, top_name, top_err * 1000,
                    bottom.x, bottom.y, bottom_name, bottom_err * 1000))
        t0 = rospy.get_time()
        try:
            self.stacker.run(top, bottom)
        except StackError as exc:
            return self.finish(False, "%s" % exc, t0, top_name, bottom_name, None)
        progress("released; judging the stack 5 s after the release")
        outcome = self.stacker.judge(top_name, bottom_name)
        return self.finish(outcome.success, "%s on %s %s" % (top_name, bottom_name, outcome.text), t0,
                           top_name, bottom_name, outcome)

    def finish(self, ok, text, t0, top_name, bottom_name, outcome):
        line = "RESULT: %s: %s (%.1f s simulated)" % ("success" if ok else "failure", text,
                                                      rospy.get_time() - t0)
        print(line, flush=True)
        rospy.loginfo(line)
        if self.result_file:
            with open(self.result_file, "w") as f:
                f.write("success: %s\ntop: %s\nbottom: %s\n"
                        % ("true" if ok else "false", top_name, bottom_name))
                if outcome is not None:
                    f.write("tilt_deg: %.3f\noffset_m: %.5f\nheight_error_m: %.5f\n"
                            % (outcome.tilt_deg, outcome.offset, outcome.height_error))
                f.write("text: \"%s\"\n" % text.replace('"', "'"))
                f.write("sim_time: %.3f\n" % rospy.get_time())     # simulated s since the world started
        if self.plot_dir:
            from katana_sim.plots import plot_joint_tracking
            os.makedirs(self.plot_dir, exist_ok=True)
            with self.arm.lock:
                log = list(self.arm.joint_log)
            path = plot_joint_tracking(log,
                                       os.path.join(self.plot_dir, "katana_joint_tracking.png"))
            progress("joint tracking plot: %s" % path)
        return ok


def progress(text):
    print("[katana] %s" % text, flush=True)


def main():
    rospy.init_node("can_stacker")
    try:
        node = CanStackNode()
        ok = node.run()
    except KatanaError as exc:
        print("RESULT: failure: %s" % exc, flush=True)
        rospy.logerr("can_stacker: %s" % exc)
        ok = None
    finish_scenario(progress, rospy.get_param("~exit_when_done", False), rospy.is_shutdown)
    return 2 if ok is None else 0 if ok else 1
