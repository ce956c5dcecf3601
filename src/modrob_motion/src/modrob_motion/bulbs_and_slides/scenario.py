"""The pick-and-place on a running simulation (ROS layer).

one_robot:  modrob0 (6-DoF + gripper) takes the bulb waiting at the red slide's tip, lifts it clear
            of the slides, carries it over the blue slide and releases it there.
two_robots: modrob0 (3-DoF) takes the bulb at the red tip and lays it in the cradle between the
            robots; modrob1 (3-DoF) takes it from the cradle and releases it over the blue slide.
            Only one arm is near the cradle at any time (the other waits turned away).
Success: the bulb comes to rest inside the blue slide's channel.
"""
import contextlib
import math
import random
import time

import numpy as np
import rospy

from modrob_kinematics.kdl_urdf import KinematicChain
from modrob_motion.bulbs_and_slides import ScenarioError
from modrob_motion.bulbs_and_slides.clearance import clearance, positions_by_model, skeleton, urdf_parents
from modrob_motion.bulbs_and_slides.grasp_ik import GraspIk
from modrob_motion.bulbs_and_slides.layout import bulb_grasp_point
from modrob_motion.bulbs_and_slides.outcome import RestWindow, expected_rest, on_slide
from modrob_motion.bulbs_and_slides.planner import ArmPlanner, Segment, plan_pick_and_place
from modrob_motion.bulbs_and_slides.recording import Recorder
from modrob_motion.bulbs_and_slides.ros_robot import RosArm, WorldMonitor, sim_sleep
from modrob_motion.bulbs_and_slides.trajectory import time_waypoints
from modrob_motion.cartesian import default_tip
from modrob_motion.robot_info import robot_info_from_urdf


LIFT_LOST = 0.02    # m: a bulb further than this from the grasp centre after a lift is lost
ARMS_TOUCH = 0.10   # m: two module radii (housings up to 100 mm across); closer skeletons may touch
JS_LAG_SHOWN = 0.5  # s: the RESULT line tells when joint_states reached the scenario this late


@contextlib.contextmanager
def physics_paused():
    """The simulation paused (/gazebo/pause_physics) for a stretch of pure computation such as the
    planning: at real-time factor 0 the simulator would otherwise run on idle for as long as the
    plan takes, competing with it for the CPU, piling up joint_states that this process does not
    read meanwhile (it then reads them seconds late), and adding simulated seconds in which
    nothing happens to the run's pace. Unpaused afterwards, whatever happens, unless it was paused
    already (someone paused it: it stays paused). Without the services (another simulator), it warns
    and computes with the simulation running."""
    from gazebo_msgs.srv import GetPhysicsProperties
    from std_srvs.srv import Empty
    paused_here = False
    try:
        rospy.wait_for_service("/gazebo/pause_physics", timeout=5.0)
        if not rospy.ServiceProxy("/gazebo/get_physics_properties", GetPhysicsProperties)().pause:
            rospy.ServiceProxy("/gazebo/pause_physics", Empty)()
            paused_here = True
    except (rospy.ROSException, rospy.ServiceException) as exc:
        rospy.logwarn("could not pause the simulation (%s); planning with it running", exc)
    try:
        yield
    finally:
        if paused_here:
            rospy.ServiceProxy("/gazebo/unpause_physics", Empty)()


class Result(object):
    def __init__(self):
        self.success = False
        self.message = ""
        self.sim_time = 0.0
        self.wall_time = 0.0
        self.grasp_force = float("nan")
        self.placement_error = float("nan")
        self.bulb = None
        self.final_position = None
        self.clearance = float("nan")      # two robots: closest approach of the arms' skeletons [m]
        self.sim_alone_rtf = float("nan")  # the simulator's pace right after the run (measure_pace)
        self.setpoints = 0                 # arm set-points streamed, and those more than 20 ms of
        self.late_setpoints = 0            # simulated time after the one before (the stream fell behind)
        self.js_lag = 0.0                  # the latest a joint_states message reached the scenario [sim s]
        # from the first gripper close to the last open: simulated and wall s (the grasp's contacts
        # make these steps the costliest of the run: docs/benchmarks.md)
        self.held_sim_time = 0.0
        self.held_wall_time = 0.0
        self._held_from = None
        # how far the bulb's glass centre is from the grasp centre after a lift [m] (the largest of
        # the run's lifts): the grasp slips along the approach in some lifts, and a lift fails above
        # LIFT_LOST; the margin shows here before it shows as a failure
        self.lift_offset = float("nan")

    def lifted(self, offset):
        """Record the bulb's offset from the grasp centre after a lift [m]."""
        if math.isnan(self.lift_offset) or offset > self.lift_offset:
            self.lift_offset = float(offset)

    def holding(self, closing):
        """Mark a gripper close (``closing``) or open, at the current simulated and wall time."""
        now = (rospy.get_time(), time.time())
        if closing:
            if self._held_from is None:
                self._held_from = now
        elif self._held_from is not None:
            self.held_sim_time = now[0] - self._held_from[0]
            self.held_wall_time = now[1] - self._held_from[1]

    def line(self, scenario):
        return ("RESULT %s: %s, sim time %.2f s, wall %.1f s (real-time factor %.2f), grasp force %.2f N, "
                "placement error %.1f mm%s%s%s%s%s"
                % (scenario, "SUCCESS" if self.success else "FAILURE", self.sim_time, self.wall_time,
                   self.sim_time / self.wall_time if self.wall_time > 0 else 0.0, self.grasp_force,
                   1000 * self.placement_error,
                   "" if math.isnan(self.clearance) else
                   ", arms' closest approach %.0f mm" % (1000 * self.clearance),
                   ", %d of %d set-points late" % (self.late_setpoints, self.setpoints)
                   if self.late_setpoints else "",
                   ", joint_states up to %.1f s late" % self.js_lag if self.js_lag >= JS_LAG_SHOWN else "",
                   "" if math.isnan(self.sim_alone_rtf) else
                   ", simulator alone %.2f" % self.sim_alone_rtf,
                   (" -- " + self.message) if self.message else ""))

    def as_dict(self):
        return {"success": self.success, "message": self.message, "sim_time": self.sim_time,
                "wall_time": self.wall_time, "grasp_force": self.grasp_force,
                "placement_error": self.placement_error, "bulb": self.bulb,
                "clearance": self.clearance, "sim_alone_rtf": self.sim_alone_rtf,
                "setpoints": self.setpoints, "late_setpoints": self.late_setpoints, "js_lag": self.js_lag,
                "held_sim_time": self.held_sim_time, "held_wall_time": self.held_wall_time,
                "lift_offset": self.lift_offset,
                "final_position": None if self.final_position is None else
                [float(v) for v in self.final_position]}


class Robot(object):
    """Everything about one robot: RobotInfo, KDL chain to the grasp centre, IK, planner, ROS arm."""

    def __init__(self, robot_id, min_down_deg=30.0, max_tilt_deg=35.0):
        urdf = rospy.get_param("/modrob%d/robot_description" % robot_id, None)
        deadline = time.time() + 60.0
        while not urdf and time.time() < deadline and not rospy.is_shutdown():
            time.sleep(0.2)
            urdf = rospy.get_param("/modrob%d/robot_description" % robot_id, None)
        if not urdf:
            raise ScenarioError("no /modrob%d/robot_description: did the robots spawn?" % robot_id)
        self.info = robot_info_from_urdf(robot_id, urdf)
        tip = default_tip(urdf, self.info.gripper.joints if self.info.gripper else [])
        self.chain = KinematicChain.from_urdf_string(urdf, tip_link=tip)
        if self.chain.joint_names != self.info.arm_joints:
            raise ScenarioError("modrob%d: the chain to %s moves %s, the arm has %s"
                                % (robot_id, tip, self.chain.joint_names, self.info.arm_joints))
        self.ik = GraspIk(self.chain, min_down=math.radians(min_down_deg), max_tilt_deg=max_tilt_deg)
        self.planner = ArmPlanner(self.ik)
        self.arm = RosArm(self.info)

    def fk(self, q):
        return self.chain.fk_position(list(q))


class ClearanceMonitor(object):
    """The closest approach of two robots' skeletons (link frame to parent link frame) over a run,
    from /gazebo/link_states; see :mod:`.clearance`."""

    def __init__(self, robot_ids):
        from gazebo_msgs.msg import LinkStates
        self.models = ["modrob%d" % i for i in robot_ids]
        self.parents = {}
        for m in self.models:
            self.parents[m] = urdf_parents(rospy.get_param("/%s/robot_description" % m))
        self.closest = (float("inf"), None, None, None)    # distance, link pair a, b, sim time
        self.samples = 0
        self.sub = rospy.Subscriber("/gazebo/link_states", LinkStates, self._on_links, queue_size=1)

    def _on_links(self, msg):
        pos = positions_by_model(msg.name, [(p.position.x, p.position.y, p.position.z) for p in msg.pose],
                                 self.models)
        if not all(pos[m] for m in self.models):
            return
        a, b = (skeleton(self.parents[m], pos[m]) for m in self.models)
        d, na, nb = clearance(a, b)
        self.samples += 1
        if d < self.closest[0]:
            self.closest = (d, na, nb, rospy.get_time())

    def stop(self):
        self.sub.unregister()


def _log(msg):
    print(msg, flush=True)


class Scenario(object):
    MOTIONS = ("trajectory", "stream")

    def __init__(self, layout, log=_log, jitter=0.0, seed=0, arm_speed=0.5, motion="trajectory"):
        """motion: 'trajectory' (each segment sent whole to a JointTrajectoryController that the
        simulator runs, RosArm.use_trajectory_controller) or 'stream' (set-points streamed at
        100 Hz of simulated time through motion_publisher, the seed's way)."""
        if motion not in self.MOTIONS:
            raise ScenarioError("motion must be one of %s, got %r" % (", ".join(self.MOTIONS), motion))
        self.motion = motion
        self.layout = layout
        self.log = log
        self.jitter = jitter
        self.rng = random.Random(seed)
        self.arm_speed = arm_speed
        self.world = WorldMonitor()
        self.robots = {}
        self.recorder = None
        self.t0 = None

    # ---- common -------------------------------------------------------------------------
    def setup(self, robot_ids):
        self.world.wait()
        for rid in robot_ids:
            self.robots[rid] = Robot(rid)
        self.recorder = Recorder({rid: r.fk for rid, r in self.robots.items()}, clock=rospy.get_time)
        for r in self.robots.values():
            r.arm.recorder = self.recorder
            r.arm.wait_ready()
            if self.motion == "trajectory":
                r.arm.use_trajectory_controller()
        self.t0 = rospy.get_time()
        self.wall0 = time.time()

    def release(self):
        """The arms back on their position controllers (motion_publisher drives them again)."""
        for r in self.robots.values():
            r.arm.release_trajectory_controller()

    def stream_stats(self, result):
        """Copy the robots' set-point counts into ``result``."""
        result.setpoints = sum(r.arm.setpoints for r in self.robots.values())
        result.late_setpoints = sum(r.arm.late_setpoints for r in self.robots.values())
        lag = max(self.robots.values(), key=lambda r: r.arm.js_lag, default=None)
        if lag is not None and lag.arm.js_lag_at is not None:
            result.js_lag = lag.arm.js_lag
            self.log("  joint_states reached the scenario up to %.2f s of simulated time late (modrob%d, at "
                     "%.2f s)" % (lag.arm.js_lag, lag.info.robot_id, lag.arm.js_lag_at - self.t0))

    def measure_pace(self, seconds):
        """The simulator's real-time factor over ``seconds`` of wall time with nothing commanded (the
        robots holding their last set-points): the reference for a run's own factor. A measurement
        window in wall time, not a wait for a condition."""
        s0, w0 = rospy.get_time(), time.time()
        time.sleep(seconds)
        return (rospy.get_time() - s0) / (time.time() - w0)

    def bulbs(self):
        return sorted(n for n in self.world.names() if n.startswith("bulb"))

    def glass_centre(self, name):
        pose = self.world.pose(name)
        return bulb_grasp_point(self.layout, pose)

    def wait_at_rest(self, names, timeout=10.0, window=0.5):
        """True once every bulb of ``names`` has been at rest for ``window`` s of simulated time
        (sampled every 0.02 s, or as often as this process gets to), False after ``timeout``."""
        end = rospy.get_time() + timeout
        rest = {n: RestWindow(window) for n in names}
        while not rospy.is_shutdown():
            t = rospy.get_time()
            if t >= end:
                break
            for n in names:
                rest[n].add(t, self.world.speed(n) or 0.0)
            if all(r.at_rest() for r in rest.values()):
                return True
            sim_sleep(0.02)
        return False

    def tip_bulb(self):
        """The bulb waiting at the red tip (nearest to the first resting place there)."""
        want = expected_rest(self.layout, "red_slide", 0)
        best = None
        for n in self.bulbs():
            c, _ = self.glass_centre(n)
            d = float(np.linalg.norm(c - want))
            if best is None or d < best[0]:
                best = (d, n)
        if best is None or best[0] > 0.03:
            raise ScenarioError("no bulb at the red slide's tip (nearest %s, %.3f m away)"
                                % (best[1] if best else "none", best[0] if best else float("nan")))
        return best[1]

    def apply_jitter(self, name):
        """Shift the bulb by a few mm (seeded): along the slide it slides back to the stop, across it
        stays off-centre -- the pick must cope with both."""
        if self.jitter <= 0:
            return
        from gazebo_msgs.msg import ModelState
        from gazebo_msgs.srv import SetModelState
        pose = self.world.pose(name)
        dx = self.rng.uniform(-self.jitter, self.jitter)
        dy = self.rng.uniform(-self.jitter, self.jitter)
        st = ModelState(model_name=name, reference_frame="world")
        st.pose.position.x, st.pose.position.y, st.pose.position.z = pose[0][0] + dx, pose[0][1] + dy, \
            pose[0][2] + 0.001
        (st.pose.orientation.x, st.pose.orientation.y, st.pose.orientation.z,
         st.pose.orientation.w) = pose[1]
        rospy.wait_for_service("/gazebo/set_model_state", timeout=10.0)
        res = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)(st)
        if not res.success:
            raise ScenarioError("could not jitter %s: %s" % (name, res.status_message))
        self.log("  jitter: %s moved by (%.1f, %.1f) mm" % (name, 1000 * dx, 1000 * dy))

    def run_segments(self, robot, segments, bulb, result):
        arm = robot.arm
        for seg in segments:
            self.log("  modrob%d: %s (%d points, at %.2f s)"
                     % (robot.info.robot_id, seg.name, len(seg.configs), rospy.get_time() - self.t0))
            traj = time_waypoints(robot.info.arm_joints, seg.configs, seg.speed)
            before, _ = self.glass_centre(bulb)
            arm.follow(traj)
            if seg.gripper_after == "close" or seg.name.startswith("to "):
                after, _ = self.glass_centre(bulb)
                if np.linalg.norm(after - before) > 0.005:   # the approach must not touch the bulb
                    moved = 1000 * np.linalg.norm(after - before)
                    self.log("  modrob%d: %s moved by %.1f mm during '%s' (now at %.3f, %.3f, %.3f)"
                             % ((robot.info.robot_id, bulb, moved, seg.name) + tuple(after)))
            if seg.settle:
                t_settle = rospy.get_time()
                err = arm.settle(tol=0.004 if seg.gripper_after else 0.02, timeout=3.0)
                self.log("  modrob%d: settled in %.2f s (joint error %.4f rad)"
                         % (robot.info.robot_id, rospy.get_time() - t_settle, err))
                if seg.gripper_after and err > 0.02:
                    raise ScenarioError("modrob%d did not reach the %s pose (joint error %.3f rad)"
                                        % (robot.info.robot_id, seg.name, err))
            if seg.gripper_after == "close":
                c, _ = self.glass_centre(bulb)
                off = 1000 * np.linalg.norm(c - np.array(robot.fk(arm.measured())))
                self.log("  modrob%d: at the grasp pose, bulb %.1f mm from the grasp centre"
                         % (robot.info.robot_id, off))
                result.holding(True)
                arm.gripper("close", wait=0.8)
                fingers = robot.info.gripper.joints
                result.grasp_force = float(np.mean(np.abs(arm.efforts(fingers))))
                fq = arm.measured(fingers)
                tcp = np.array(robot.fk(arm.measured()))
                c, _ = self.glass_centre(bulb)
                self.log("  modrob%d: gripper closed, %.2f N per finger, fingers at %s mm, bulb %.1f mm from "
                         "the grasp centre" % (robot.info.robot_id, result.grasp_force,
                                               "/".join("%.1f" % (1000 * v) for v in fq),
                                               1000 * np.linalg.norm(c - tcp)))
            elif seg.gripper_after == "open":
                arm.gripper("open", wait=0.4)
                result.holding(False)
                c, _ = self.glass_centre(bulb)
                self.log("  modrob%d: gripper opened, %s at (%.3f, %.3f, %.3f)"
                         % ((robot.info.robot_id, bulb) + tuple(c)))
            if seg.name == "lift":
                # the bulb's pose (model_states) and the arm's (joint_states) come on two topics; in a
                # fast run this process can be behind the simulator by tens of milliseconds, and the
                # two need not be equally late: compared while the bulb still rises, a model_states
                # message older than the joint_states put the bulb up to 19 mm below the grasp
                # centre when it had not moved in the grasp. Once it is at rest, both are the same.
                self.wait_at_rest([bulb], timeout=3.0, window=0.2)
                tcp = np.array(robot.fk(arm.measured()))
                c, _ = self.glass_centre(bulb)
                off = c - tcp
                dist = float(np.linalg.norm(off))
                result.lifted(dist)
                self.log("  modrob%d: lifted, bulb %.1f mm from the grasp centre (world x y z: %+.1f %+.1f "
                         "%+.1f mm)" % ((robot.info.robot_id, 1000 * dist) + tuple(1000 * off)))
                if dist > LIFT_LOST:
                    raise ScenarioError("the bulb is not in the gripper after the lift (%.1f mm from the "
                                        "grasp centre)" % (1000 * dist))

    def finish(self, result, bulb, slide="blue_slide"):
        """Judge where ``bulb`` came to rest in ``slide``: behind the bulbs the world put there."""
        rest = self.wait_at_rest([bulb], timeout=10.0)
        c, axis = self.glass_centre(bulb)
        result.final_position = c
        result.bulb = bulb
        socket_first = float(np.dot(axis, self.layout.slides[slide].uphill)) < 0.0
        if socket_first:
            self.log("  %s lies socket first (turned round by the hand-over)" % bulb)
        want = expected_rest(self.layout, slide, self.layout.bulbs_waiting_on(slide), socket_first)
        result.placement_error = float(np.linalg.norm(c - want))
        result.sim_time = rospy.get_time() - self.t0
        result.wall_time = time.time() - self.wall0
        if not rest:
            result.message = "%s still moving after 10 s" % bulb
        elif not on_slide(self.layout, slide, c):
            s, lat, h = self.layout.slides[slide].coordinates(c)
            result.message = ("%s came to rest off the %s (along %.3f m, across %.3f m, height %.3f m)"
                              % (bulb, slide, s, lat, h))
        else:
            result.success = True

    # ---- one robot ----------------------------------------------------------------------
    def run_one_robot(self):
        result = Result()
        self.log("[1/5] waiting for the simulation and modrob0")
        self.setup([0])
        r = self.robots[0]
        r.arm.gripper("open", wait=0.3)
        bulb = self.tip_bulb()
        self.apply_jitter(bulb)
        self.log("[2/5] waiting for %s to rest at the red tip" % bulb)
        self.wait_at_rest(self.bulbs(), timeout=5.0)
        grasp, axis = self.glass_centre(bulb)
        self.log("  %s glass centre at (%.3f, %.3f, %.3f)" % ((bulb,) + tuple(grasp)))
        self.log("[3/5] planning (grasp IK with KDL forward kinematics)")
        blue = self.layout.slides["blue_slide"]
        q_start = r.arm.measured()
        wall = time.time()
        with physics_paused():
            segs = plan_pick_and_place(r.planner, q_start, grasp, axis, self.layout.place_point,
                                       blue.uphill, fast=self.arm_speed)
        self.log("[4/5] pick and place (planned in %.1f s of wall time, the simulation paused)"
                 % (time.time() - wall))
        try:
            self.run_segments(r, segs, bulb, result)
        except ScenarioError as exc:
            result.message = str(exc)
            result.sim_time = rospy.get_time() - self.t0
            result.wall_time = time.time() - self.wall0
            return result
        self.log("[5/5] waiting for %s to come to rest" % bulb)
        self.finish(result, bulb)
        return result

    # ---- two robots ---------------------------------------------------------------------
    def run_two_robots(self, hover=0.12, drop_gap=0.004):
        """modrob0: red tip -> cradle; modrob1: cradle -> over the blue slide. Both 3-DoF arms work
        in joint space: yaw (joint1) towards the target, pitch (joint2) so that the arm is
        horizontal at the target's height (the layout puts every target one arm's length away at
        the shoulder's height), roll (joint3) 0 so that the fingers close horizontally; they come
        down onto a bulb by raising/lowering joint2 by ``hover`` rad. Only one arm is near the
        cradle at any time: modrob1 waits upright until modrob0 has parked."""
        result = Result()
        self.log("[1/6] waiting for the simulation, modrob0 and modrob1")
        self.setup([0, 1])
        self.clearance = ClearanceMonitor([0, 1])
        r0, r1 = self.robots[0], self.robots[1]
        for r, (order, base) in zip((r0, r1), self.layout.robots):
            q0 = r.chain.fk_position([0.0, 0.0, 0.0])
            if abs(q0[0] - base[0]) > 0.01 or abs(q0[1] - base[1]) > 0.01:
                raise ScenarioError("modrob%d stands at (%.3f, %.3f), the layout wants (%.3f, %.3f): the "
                                    "launch file's bases and bulbs_and_slides_layout.yaml disagree"
                                    % (r.info.robot_id, q0[0], q0[1], base[0], base[1]))
        r0.arm.gripper("open", wait=0.2)
        r1.arm.gripper("open", wait=0.2)
        bulb = self.tip_bulb()
        self.apply_jitter(bulb)
        self.log("[2/6] waiting for %s to rest at the red tip" % bulb)
        self.wait_at_rest(self.bulbs(), timeout=5.0)
        try:
            grasp, _ = self.glass_centre(bulb)
            q_pick = self._arm3_target(r0, grasp)
            q_cradle0 = self._arm3_target(r0, self.layout.cradle_point)
            self.log("[3/6] modrob0: red tip -> cradle")
            segs = self._arm3_pick_place(r0.arm.measured(), q_pick, q_cradle0, hover, drop_gap,
                                         park=[-math.pi / 2, 0.5, 0.0])
            self.run_segments(r0, segs, bulb, result)
            self.log("[4/6] waiting for %s to rest in the cradle" % bulb)
            self.wait_at_rest([bulb], timeout=5.0)
            c, _ = self.glass_centre(bulb)
            if np.linalg.norm(c - self.layout.cradle_point) > 0.03:
                off = 1000 * np.linalg.norm(c - self.layout.cradle_point)
                raise ScenarioError("%s is not in the cradle (%.1f mm from it, at (%.3f, %.3f, %.3f))"
                                    % ((bulb, off) + tuple(c)))
            self.log("[5/6] modrob1: cradle -> blue slide")
            q_pick1 = self._arm3_target(r1, c)
            q_drop = self._arm3_target(r1, self.layout.place_point)
            segs = self._arm3_pick_place(r1.arm.measured(), q_pick1, q_drop, hover, 0.0,
                                         park=[0.0, 0.3, 0.0])
            self.run_segments(r1, segs, bulb, result)
        except ScenarioError as exc:
            result.message = str(exc)
            result.sim_time = rospy.get_time() - self.t0
            result.wall_time = time.time() - self.wall0
            self._judge_clearance(result)
            return result
        self.log("[6/6] waiting for %s to come to rest" % bulb)
        self.finish(result, bulb)
        self._judge_clearance(result)
        return result

    def _judge_clearance(self, result):
        """The arms must not have touched: their skeletons stayed farther apart than two module radii
        (ARMS_TOUCH) at every /gazebo/link_states sample."""
        mon = self.clearance
        mon.stop()
        d, na, nb, t = mon.closest
        if mon.samples == 0:
            result.success = False
            result.message = (result.message + "; " if result.message else "") + \
                "no /gazebo/link_states received: cannot tell whether the arms collided"
            return
        result.clearance = d
        self.log("  closest approach of the arms: %.0f mm (modrob0 %s, modrob1 %s, at %.1f s; %d samples)"
                 % (1000 * d, na, nb, t - self.t0, mon.samples))
        if d < ARMS_TOUCH:
            result.success = False
            result.message = (result.message + "; " if result.message else "") + \
                ("the arms came within %.0f mm of each other (modrob0 %s, modrob1 %s at %.1f s)"
                 % (1000 * d, na, nb, t - self.t0))

    @staticmethod
    def _arm3_target(robot, point):
        """(yaw, pitch, 0) putting a 3-DoF arm's grasp centre at ``point``: yaw towards it, pitch from
        the height difference (arm length from the KDL chain at the stretched pose)."""
        base = np.array(robot.chain.fk_position([0.0, 0.0, 0.0]))
        top = robot.chain.fk_position([0.0, math.pi / 2, 0.0])
        shoulder = np.array([base[0], base[1], top[2]])
        shoulder_to_tcp = float(np.linalg.norm(np.array(top) - shoulder))
        d = np.asarray(point, dtype=float) - shoulder
        horiz = math.hypot(d[0], d[1])
        yaw = math.atan2(d[1], d[0])
        pitch = math.pi / 2 - math.asin(max(-1.0, min(1.0, d[2] / shoulder_to_tcp)))
        if abs(math.hypot(horiz, d[2]) - shoulder_to_tcp) > 0.01:
            raise ScenarioError("(%.3f, %.3f, %.3f) is %.3f m from modrob%d's shoulder; its arm is %.3f m "
                                "long" % (tuple(point) + (math.hypot(horiz, d[2]), robot.info.robot_id,
                                                          shoulder_to_tcp)))
        return np.array([yaw, pitch, 0.0])

    def _arm3_pick_place(self, q_now, q_pick, q_place, hover, gap, park):
        up = np.array([0.0, -hover, 0.0])
        above_pick, above_place = q_pick + up, q_place + up
        place = q_place + np.array([0.0, -gap, 0.0])
        fast, slow = self.arm_speed, 0.15
        return [Segment("to above the bulb", [q_now, above_pick], fast),
                Segment("descend to the bulb", [above_pick, q_pick], slow, gripper_after="close"),
                Segment("lift", [q_pick, above_pick], slow),
                Segment("swing to the release point", [above_pick, above_place], fast * 0.6),
                Segment("lower", [above_place, place], slow, gripper_after="open"),
                Segment("retreat", [place, above_place], slow, settle=False),
                Segment("park", [above_place, np.array(park)], fast, settle=False)]

    # ---- grasp sanity -------------------------------------------------------------------
    def grasp_and_lift(self):
        """Pick the red-tip bulb with modrob0 as the pick-and-place does, lift it and raise it 0.12 m
        clear of the slides (for the grasp sanity tests, which then shake the arm). A failed segment
        is logged, not raised: the tests measure where the bulb is. Returns the bulb's name."""
        self.setup([0])
        r = self.robots[0]
        r.arm.gripper("open", wait=0.3)
        bulb = self.tip_bulb()
        self.wait_at_rest(self.bulbs(), timeout=5.0)
        grasp, axis = self.glass_centre(bulb)
        blue = self.layout.slides["blue_slide"]
        segs = plan_pick_and_place(r.planner, r.arm.measured(), grasp, axis, self.layout.place_point,
                                   blue.uphill, fast=self.arm_speed)
        result = Result()
        try:
            self.run_segments(r, segs[:3], bulb, result)    # pre-grasp, descend + close, lift
            # then well clear of the slides, so that shaking hits nothing
            q = r.arm.measured()
            p0 = np.array(r.fk(q))
            up = r.planner.line(q, p0, p0 + np.array([0.0, 0.0, 0.12]), axis)
            self.run_segments(r, [Segment("raise", [q] + up, 0.2)], bulb, result)
        except ScenarioError as exc:
            self.log("  %s" % exc)
        self.release()
        return bulb
