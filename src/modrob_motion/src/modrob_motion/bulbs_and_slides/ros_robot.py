"""ROS layer: one robot commanded through its motion_publisher, and the world read from /gazebo.

Time is the simulation's (use_sim_time): every wait is in simulated seconds with a wall-clock guard
so that a stopped simulation cannot hang the scenario."""
import threading
import time

import numpy as np
import rospy
from gazebo_msgs.msg import ModelStates
from sensor_msgs.msg import JointState

from modrob_motion.bulbs_and_slides import ScenarioError


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


class RosArm(object):
    """info: motion.robot_info.RobotInfo of the robot."""

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

    def _on_js(self, msg):
        with self._lock:
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

    def follow(self, traj, rate=100.0, max_advance=0.02):
        """Stream the trajectory's set-points until its end, on a StreamClock (simulated time, at
        most ``max_advance`` per set-point: a late node resumes instead of jumping).

        The set-points keep a fixed schedule of ``rate`` per simulated second (as rospy.Rate):
        /clock comes in steps (the launch file's 250 per wall second are 9.6 ms of simulated time
        each at real-time factor 2.4), and a full period slept after each wake-up ends one step
        late (there: every second step, 19 ms between set-points instead of 10). A node late by
        more than a period starts a new schedule instead of bursting."""
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

    def settle(self, tol=0.01, timeout=4.0):
        """Wait until every arm joint is within ``tol`` of its command; returns the largest error."""
        end = rospy.get_time() + timeout
        names = self.info.arm_joints
        target = np.array([self.cmd.get(n, 0.0) for n in names])
        err = float("inf")
        while not rospy.is_shutdown() and rospy.get_time() < end:
            err = float(np.max(np.abs(self.measured(names) - target)))
            if self.recorder:
                self.recorder.sample(self)
            if err < tol:
                return err
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
            t0 = rospy.get_time()
            while not rospy.is_shutdown():
                s = min(1.0, (rospy.get_time() - t0) / ramp)
                self.command(names, start + s * (goal - start))
                if self.recorder:
                    self.recorder.sample(self)
                if s >= 1.0:
                    break
                sim_sleep(0.01)
        self.command(names, goal)
        end = rospy.get_time() + wait
        while rospy.get_time() < end and not rospy.is_shutdown():
            if self.recorder:
                self.recorder.sample(self)
            sim_sleep(0.01)
