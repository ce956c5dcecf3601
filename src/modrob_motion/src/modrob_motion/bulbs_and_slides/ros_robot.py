"""ROS layer: one robot commanded through its motion_publisher, and the world read from /gazebo.

Time is the simulation's (use_sim_time): every wait is in simulated seconds with a wall-clock guard
so that a stopped simulation cannot hang the scenario."""
import threading
import time

import numpy as np
import rospy
from gazebo_msgs.msg import ModelStates
from sensor_msgs.msg import JointState

from modrob_motion.bulbs_and_slides import ScenarioError, outcome
from modrob_motion.errors import MotionError
from modrob_motion.robot_info import parse_urdf_joints
from modrob_sim import waits


class WorldMonitor(object):
    """Latest /gazebo/model_states: pose and linear speed per model."""

    def __init__(self):
        self._lock = threading.Lock()
        self.poses = {}
        self.speeds = {}
        self.stamp = None
        self.sub = rospy.Subscriber("/gazebo/model_states", ModelStates, self._on_states, queue_size=1)

    def _on_states(self, msg):
        with self._lock:
            for name, pose, twist in zip(msg.name, msg.pose, msg.twist):
                p, o, v = pose.position, pose.orientation, twist.linear
                self.poses[name] = ((p.x, p.y, p.z), (o.x, o.y, o.z, o.w))
                self.speeds[name] = float(np.sqrt(v.x * v.x + v.y * v.y + v.z * v.z))
            self.stamp = rospy.get_time()

    def pose(self, name):
        with self._lock:
            return self.poses.get(name)

    def speed(self, name):
        with self._lock:
            return self.speeds.get(name)

    def names(self):
        with self._lock:
            return list(self.poses)

    def wait(self, timeout=30.0):
        deadline = time.time() + timeout
        while not rospy.is_shutdown() and time.time() < deadline:
            if self.stamp is not None:
                return
            time.sleep(0.05)
        raise ScenarioError("no /gazebo/model_states within %.0f s: is the simulator running?" % timeout)


class StreamClock(object):
    """The time of a set-point stream: simulated time, but advancing by at most ``max_step`` per
    set-point. The simulation runs as fast as it can and does not wait for the node streaming
    set-points: when that node is late (a loaded machine stalls it for up to 0.3 s of simulated
    time), a trajectory sampled by simulated time jumps -- a set-point step, which the position
    controllers turn into a jolt at the effort limit (it threw bulbs out of the gripper). Capped,
    a late node slows the motion down for a moment instead. ``capped`` counts the late set-points."""

    def __init__(self, max_step=0.02):
        self.max_step = max_step
        self.last = rospy.get_time()
        self.t = 0.0
        self.capped = 0

    def tick(self):
        now = rospy.get_time()
        dt = now - self.last
        self.last = now
        if dt > self.max_step:
            dt = self.max_step
            self.capped += 1
        self.t += max(0.0, dt)
        return self.t


def sim_sleep(seconds, wall_guard=120.0):
    """Sleep ``seconds`` of simulated time (see :func:`sim_sleep_until`)."""
    sim_sleep_until(rospy.get_time() + seconds, wall_guard)


def sim_sleep_until(end, wall_guard=120.0):
    """Sleep until the simulated time ``end``; ScenarioError when the clock does not move for
    ``wall_guard`` s.

    Woken by each /clock message (rospy's time condition, as rospy.sleep), so the caller resumes
    within one /clock message of the end instead of after a wall-clock poll period: at real-time
    factor 5 a 2 ms poll was 10 ms of simulated time, a whole set-point period. Not rospy.sleep
    itself: that waits forever on a stopped clock and raises on a world reset."""
    if rospy.rostime.is_wallclock():        # no simulated time: nothing to wake us
        time.sleep(max(0.0, end - rospy.get_time()))
        return
    cond = rospy.rostime.get_rostime_cond()
    last_t, last_wall = rospy.get_time(), time.time()
    while not rospy.is_shutdown():
        with cond:
            # checked under the condition's lock: /clock sets the time, then notifies under it
            now = rospy.get_time()
            if now >= end:
                return
            cond.wait(0.1)
        now = rospy.get_time()
        if now != last_t:
            last_t, last_wall = now, time.time()
        elif time.time() - last_wall > wall_guard:
            raise ScenarioError("the simulated clock stopped at %.3f s" % now)
    raise ScenarioError("shut down")


TRAJECTORY_CONTROLLER = "arm_trajectory_controller"


def wait_event(event, sim_limit, what, wall_guard=30.0):
    """Wait for ``event`` (a threading.Event set by a ROS callback) for at most ``sim_limit`` s of
    simulated time: True when it is set, False when that time has passed. Woken by each /clock
    message (as sim_sleep_until); ScenarioError when the clock does not move for ``wall_guard`` s
    of wall time."""
    end = rospy.get_time() + sim_limit
    last_t, last_wall = rospy.get_time(), time.time()
    cond = None if rospy.rostime.is_wallclock() else rospy.rostime.get_rostime_cond()
    while not rospy.is_shutdown():
        if event.is_set():
            return True
        if rospy.get_time() >= end:
            return False
        if cond is None:
            event.wait(0.005)
        else:
            with cond:
                if not event.is_set() and rospy.get_time() < end:
                    cond.wait(0.1)
        now = rospy.get_time()
        if now != last_t:
            last_t, last_wall = now, time.time()
        elif time.time() - last_wall > wall_guard:
            raise ScenarioError("%s: the simulated clock stopped at %.3f s" % (what, now))
    raise ScenarioError("shut down")


class RosArm(object):
    """info: motion.robot_info.RobotInfo of the robot.

    The arm moves in one of two ways: set-points streamed through motion_publisher (``command``,
    ``follow`` before ``use_trajectory_controller``), or, after ``use_trajectory_controller``,
    each motion sent whole to an effort_controllers/JointTrajectoryController that the simulator
    runs at every step (``follow`` then waits for the action's result). The gripper always goes
    through motion_publisher."""

    def __init__(self, info, recorder=None):
        self.info = info
        self.ns = "/modrob%d" % info.robot_id
        self._lock = threading.Lock()
        self.q = {}
        self.effort = {}
        self.recorder = recorder
        self.cmd = {}
        self.setpoints = 0          # streamed by follow(), and how many of them came late (capped)
        self.late_setpoints = 0
        self.pub = rospy.Publisher(self.ns + "/motion_command", JointState, queue_size=10)
        self.sub = rospy.Subscriber(self.ns + "/joint_states", JointState, self._on_js, queue_size=5)
        self.trajectory_client = None   # actionlib client while the trajectory controller runs
        self.js_stamp = None
        self.js_lag = 0.0           # the most simulated time a joint_states message arrived after its stamp
        self.js_lag_at = None       # and the scenario's clock then
        self._effort_limits = None
        self._position_controllers = []  # the arm's position controllers it replaced
        self.trajectories = 0
        self._commanded = None

    def _on_js(self, msg):
        now = rospy.get_time()
        with self._lock:
            self.js_stamp = msg.header.stamp.to_sec()
            if now > 0.0 and now - self.js_stamp > self.js_lag:
                self.js_lag, self.js_lag_at = now - self.js_stamp, now
            self.q.update(zip(msg.name, msg.position))
            if msg.effort:
                self.effort.update(zip(msg.name, msg.effort))

    def wait_ready(self, timeout=60.0):
        deadline = time.time() + timeout
        while not rospy.is_shutdown() and time.time() < deadline:
            with self._lock:
                have = all(j in self.q for j in self.info.all_joints)
            if have and self.pub.get_num_connections() > 0:
                return
            time.sleep(0.05)
        raise ScenarioError("modrob%d not ready within %.0f s (joint states: %s, motion_publisher "
                            "listening: %s)"
                            % (self.info.robot_id, timeout, "yes" if self.q else "no",
                               "yes" if self.pub.get_num_connections() else "no"))

    def measured(self, names=None):
        with self._lock:
            return np.array([self.q[n] for n in (names or self.info.arm_joints)])

    def efforts(self, names):
        with self._lock:
            return np.array([self.effort.get(n, 0.0) for n in names])

    def command(self, names, positions):
        msg = JointState(name=list(names), position=[float(v) for v in positions])
        msg.header.stamp = rospy.Time.now()
        self.pub.publish(msg)
        self.cmd.update(zip(names, positions))

    # ---- the arm's motions timed inside the simulator -------------------------------------------
    def _controller_service(self, name, srv_type, wall_timeout=30.0):
        path = "%s/controller_manager/%s" % (self.ns, name)
        deadline = time.time() + wall_timeout
        while not rospy.is_shutdown():
            # rospy.wait_for_service's timeout is wall-clock time
            try:
                rospy.wait_for_service(path, timeout=max(0.1, min(1.0, deadline - time.time())))
                return rospy.ServiceProxy(path, srv_type)
            except rospy.ROSException:
                if time.time() >= deadline:
                    raise ScenarioError("%s did not appear within %.0f s: is the robot's controller "
                                        "manager running?" % (path, wall_timeout))
        raise ScenarioError("shut down")

    def use_trajectory_controller(self, goal_time=1.0, wall_timeout=30.0):
        """Swap the arm's JointPositionControllers for one effort_controllers/JointTrajectoryController
        with the same PID gains (ros_control's switch_controller, in one step). The controller keeps
        the motion's pace in simulated time however late this process runs; its D term acts on the
        velocity error, so a motion is a smooth effort, not a set-point pulse every 10 ms."""
        import actionlib
        from control_msgs.msg import FollowJointTrajectoryAction
        from controller_manager_msgs.srv import ListControllers, LoadController, SwitchController
        from modrob_motion.controller_map import position_controllers

        if self.trajectory_client is not None:
            return
        by_joint = position_controllers(rospy.get_param(self.ns, {}), self.ns)
        missing = [j for j in self.info.arm_joints if j not in by_joint]
        if missing:
            raise ScenarioError("modrob%d: no position controller for %s under %s"
                                % (self.info.robot_id, ", ".join(missing), self.ns))
        self._position_controllers = [by_joint[j] for j in self.info.arm_joints]
        base = "%s/%s" % (self.ns, TRAJECTORY_CONTROLLER)
        gains = {}
        for j, c in zip(self.info.arm_joints, self._position_controllers):
            pid = rospy.get_param("%s/%s/pid" % (self.ns, c), None)
            if not isinstance(pid, dict) or "p" not in pid:
                raise ScenarioError("modrob%d: %s/%s/pid has no gains" % (self.info.robot_id, self.ns, c))
            gains[j] = pid
        rospy.set_param(base, {
            "type": "effort_controllers/JointTrajectoryController",
            "joints": list(self.info.arm_joints),
            "gains": gains,
            "constraints": {"goal_time": goal_time, "stopped_velocity_tolerance": 0.05},
            "state_publish_rate": 25.0,
        })
        listed = self._controller_service("list_controllers", ListControllers, wall_timeout)()
        states = {c.name: c.state for c in listed.controller}
        if TRAJECTORY_CONTROLLER not in states:
            if not self._controller_service("load_controller", LoadController, wall_timeout)(
                    TRAJECTORY_CONTROLLER).ok:
                raise ScenarioError("modrob%d: could not load %s (see the simulator's log)"
                                    % (self.info.robot_id, base))
        # actionlib's ActionClient with a transition callback per goal (execute), not SimpleActionClient:
        # SimpleActionClient learns which goal it tracks only when send_goal returns, and the
        # simulator accepts a goal sooner than that, so its first transition was refused with
        # "[ERROR] Got a transition callback on a goal handle that we're not tracking"
        client = actionlib.ActionClient(base + "/follow_joint_trajectory", FollowJointTrajectoryAction)
        switch = self._controller_service("switch_controller", SwitchController, wall_timeout)
        if not switch(start_controllers=[TRAJECTORY_CONTROLLER], stop_controllers=self._position_controllers,
                      strictness=2, start_asap=False, timeout=0.0).ok:
            raise ScenarioError("modrob%d: could not switch to %s (see the simulator's log)"
                                % (self.info.robot_id, base))
        # actionlib's own timeout is simulated time, which at real-time factor 0 runs out at once
        if waits.wait_for_action_servers(((client, base),), wall_timeout) is not None:
            raise ScenarioError("modrob%d: %s/follow_joint_trajectory did not answer within %.0f s"
                                % (self.info.robot_id, base, wall_timeout))
        self.trajectory_client = client
        q = self.measured()
        self.cmd.update(zip(self.info.arm_joints, q))

    def release_trajectory_controller(self, wall_timeout=30.0):
        """Back to the JointPositionControllers (they start holding where the arm is), so that
        motion_publisher drives the arm again."""
        from controller_manager_msgs.srv import SwitchController
        if self.trajectory_client is None:
            return
        switch = self._controller_service("switch_controller", SwitchController, wall_timeout)
        if not switch(start_controllers=self._position_controllers, stop_controllers=[TRAJECTORY_CONTROLLER],
                      strictness=2, start_asap=False, timeout=0.0).ok:
            raise ScenarioError("modrob%d: could not switch back to the position controllers"
                                % self.info.robot_id)
        self.trajectory_client = None

    def execute(self, traj, period=0.01, margin=30.0):
        """Send ``traj`` whole to the trajectory controller (points every ``period`` s with the
        velocities of the smoothstep, so that the controller's cubic splines follow it) and wait
        for the action's result in simulated time.

        The controller starts the motion when the goal reaches it, and it always ends the goal: it
        succeeds once the arm has stopped after the last point, or aborts ``goal_time`` after it.
        ``margin`` only bounds a goal that was lost: a goal that reached the simulator late (this
        process starved while the simulation ran on, at up to 40x in bursts on a loaded machine)
        also ends late in simulated time, so a tight margin would fail a motion that went well."""
        import actionlib
        from control_msgs.msg import FollowJointTrajectoryGoal
        from trajectory_msgs.msg import JointTrajectoryPoint
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = list(traj.joint_names)
        t0 = traj.t[0]
        for t, q, qd in traj.samples(period):
            goal.trajectory.points.append(JointTrajectoryPoint(
                positions=[float(v) for v in q], velocities=[float(v) for v in qd],
                time_from_start=rospy.Duration.from_sec(t - t0)))
        done = threading.Event()
        start = rospy.get_time()
        # the commanded line of the joints plot: the trajectory from when the controller took the
        # goal (its ACTIVE status; the controller starts the motion on arrival)
        self._commanded = (traj, start)

        active = []

        def transition(gh):
            state = gh.get_comm_state()
            if state == actionlib.CommState.ACTIVE and not active:
                active.append(True)
                self._commanded = (traj, rospy.get_time())
            elif state == actionlib.CommState.DONE:
                done.set()
        handle = self.trajectory_client.send_goal(goal, transition)   # kept: actionlib holds it weakly
        self.trajectories += 1
        end_q = traj.q[-1]
        what = "modrob%d's trajectory" % self.info.robot_id
        limit = traj.duration - t0 + margin
        try:
            while not wait_event(done, 0.02, what):
                if self.recorder:
                    self.recorder.sample(self)
                if rospy.get_time() - start > limit:
                    handle.cancel()
                    raise ScenarioError("modrob%d: the trajectory controller gave no result %.1f s "
                                        "after the motion's end" % (self.info.robot_id, margin))
        finally:
            self._commanded = None
            self.cmd.update(zip(traj.joint_names, end_q))
        res = handle.get_result()
        if res is not None and res.error_code != 0:
            raise ScenarioError("modrob%d: the trajectory controller aborted the motion: %s (error %d)"
                                % (self.info.robot_id, res.error_string, res.error_code))

    def commanded(self, names):
        """What the arm is commanded now: the trajectory being executed at this simulated time, or
        the last set-point."""
        cur = self._commanded
        if cur is not None:
            traj, start = cur
            q = dict(zip(traj.joint_names, traj.sample(traj.t[0] + rospy.get_time() - start)))
            return np.array([q.get(n, self.cmd.get(n, np.nan)) for n in names])
        return np.array([self.cmd.get(n, np.nan) for n in names])

    def follow(self, traj, rate=100.0, max_advance=0.02):
        """With the trajectory controller: :meth:`execute`. Otherwise stream the trajectory's set-points
        until its end, on a StreamClock (simulated time, at most ``max_advance`` per set-point: a late
        node resumes instead of jumping).

        The set-points keep a fixed schedule of ``rate`` per simulated second (as rospy.Rate):
        /clock comes in steps (the launch file's 250 per wall second are 9.6 ms of simulated time
        each at real-time factor 2.4), and a full period slept after each wake-up ends one step
        late (there: every second step, 19 ms between set-points instead of 10). A node late by
        more than a period starts a new schedule instead of bursting."""
        if self.trajectory_client is not None:
            self.execute(traj)
            return
        clock = StreamClock(max_advance)
        period = 1.0 / rate
        wake = rospy.get_time()
        try:
            while not rospy.is_shutdown():
                t = clock.tick()
                q = traj.sample(t)
                self.command(traj.joint_names, q)
                self.setpoints += 1
                if self.recorder:
                    self.recorder.sample(self)
                if t >= traj.duration:
                    return
                now = rospy.get_time()
                wake = wake + period if wake + period > now else now + period
                sim_sleep_until(wake)
        finally:
            self.late_setpoints += clock.capped

    def settle(self, tol=0.01, timeout=4.0, wall_guard=30.0):
        """Wait until every arm joint is within ``tol`` of its command; returns the largest error.

        Judged on joint_states stamped after the wait began, and timed by their stamps: on a loaded
        machine the stream can reach this process seconds of simulated time late, and old positions
        then used up a timeout counted on the clock (a run failed with the arm "0.089 rad" from a
        pose it had reached). At most ``timeout`` s of the arm's simulated time, or ``wall_guard``
        s of wall time without that (then a warning)."""
        start = rospy.get_time()
        wall_end = time.time() + wall_guard
        names = self.info.arm_joints
        target = np.array([self.cmd.get(n, 0.0) for n in names])
        err = float("inf")
        while not rospy.is_shutdown():
            with self._lock:
                stamp = self.js_stamp
            if stamp is not None and stamp >= start:
                err = float(np.max(np.abs(self.measured(names) - target)))
                if err < tol or stamp >= start + timeout:
                    return err
            if time.time() > wall_end:
                rospy.logwarn("modrob%d: no joint_states of %.1f s after the motion within %.0f s of wall "
                              "time (the latest stamped %.2f s, the clock at %.2f s)",
                              self.info.robot_id, timeout, wall_guard, stamp or float("nan"),
                              rospy.get_time())
                return err
            if self.recorder:
                self.recorder.sample(self)
            sim_sleep(0.01)
        return err

    def gripper(self, action, wait=0.6, ramp=0.4):
        """Open or close. Closing ramps the finger targets over ``ramp`` s so that the fingers meet the
        bulb slowly and the squeeze builds up to the grip force (the effort limit) without a blow."""
        if self.info.gripper is None:
            raise ScenarioError("modrob%d has no gripper" % self.info.robot_id)
        target = self.info.gripper.command(action)
        names = list(target)
        goal = np.array([target[n] for n in names])
        if action == "close" and ramp > 0:
            # from where the fingers are, but inside the open..closed range: a finger resting a hair
            # beyond its limit at the open stop would otherwise make motion_publisher drop the first
            # set-point as out of limits
            opened = self.info.gripper.command("open")
            ends = np.array([[opened[n], target[n]] for n in names])
            start = np.clip(self.measured(names), ends.min(axis=1), ends.max(axis=1))
            # on a StreamClock: a stalled stream resumes the ramp instead of slamming the fingers shut
            clock = StreamClock(0.02)
            while not rospy.is_shutdown():
                s = min(1.0, clock.tick() / ramp)
                self.command(names, start + s * (goal - start))
                if self.recorder:
                    self.recorder.sample(self)
                if s >= 1.0:
                    break
                sim_sleep(0.01)
        self.command(names, goal)
        self._wait_fingers(action, names, goal)
        end = rospy.get_time() + wait
        while rospy.get_time() < end and not rospy.is_shutdown():
            if self.recorder:
                self.recorder.sample(self)
            sim_sleep(0.01)

    def _wait_fingers(self, action, names, goal, timeout=10.0, wall_guard=20.0, wall_min=5.0):
        """Wait until the fingers show in joint_states that the command took effect
        (outcome.fingers_done: at the goal, or stopped on the object at the grip force).

        The command goes through motion_publisher, another process: on a loaded machine at
        real-time factor 0 the simulation can run on for seconds of simulated time before it lands,
        and a fixed wait in simulated time then let the lift start with the fingers still open (the
        bulb left on the slide, seen with two runs side by side; joint_states themselves reached
        this process up to 3 simulated s late then). At most ``timeout`` s of simulated time, but
        never less than ``wall_min`` s of wall time (at real-time factor 11 on a machine at load 15,
        10 simulated s were 0.9 wall s, less than motion_publisher took to pass the command on: the
        fingers had not moved, the lift left the bulb behind), or ``wall_guard`` s of wall time
        (then a warning). Only joint_states stamped after the command count, and they time the
        wait (see :meth:`settle`)."""
        limits = self._finger_effort_limits(names)
        start = rospy.get_time()
        wall_start = time.time()
        wall_end = wall_start + wall_guard
        last_q = last_stamp = None
        settled = 0                 # fresh joint_states samples in a row that say done
        while not rospy.is_shutdown():
            with self._lock:
                stamp = self.js_stamp
            q = self.measured(names)
            if stamp != last_stamp and stamp >= start:
                moved = None if last_q is None else q - last_q
                last_q, last_stamp = q, stamp
                done = outcome.fingers_done(q, goal, self.efforts(names), limits, moved)
                settled = settled + 1 if done else 0
                if settled >= 3:
                    return True
            sim_out = last_stamp is not None and last_stamp > start + timeout
            if (sim_out and time.time() > wall_start + wall_min) or time.time() > wall_end:
                rospy.logwarn("modrob%d: the gripper did not %s within %.1f s "
                              "(fingers at %s mm, efforts %s N)",
                              self.info.robot_id, action, timeout,
                              "/".join("%.1f" % (1000 * v) for v in q),
                              "/".join("%.2f" % v for v in self.efforts(names)))
                return False
            if self.recorder:
                self.recorder.sample(self)
            sim_sleep(0.01)
        return False

    def _finger_effort_limits(self, names):
        """The fingers' effort limits from <ns>/robot_description (the grip force), NaN where none."""
        if self._effort_limits is None:
            self._effort_limits = {}
            try:
                joints = parse_urdf_joints(rospy.get_param(self.ns + "/robot_description"))
                self._effort_limits = {j.name: j.effort for j in joints if j.effort is not None}
            except (KeyError, MotionError, ValueError) as exc:
                rospy.logwarn("modrob%d: no effort limits from %s/robot_description (%s): the gripper "
                              "counts as done only at its goal" % (self.info.robot_id, self.ns, exc))
        return np.array([self._effort_limits.get(n, np.nan) for n in names])
