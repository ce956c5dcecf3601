"""apply_body_wrench / apply_joint_effort with Gazebo's timing (start_time, duration, until
cleared): jobs that become active in the before-step hook. Pure; loop thread only."""
import logging

LOG = logging.getLogger("modrob_sim.gazebo_ros")


class _EffortJob(object):
    __slots__ = ("joint", "effort", "start", "end")

    def __init__(self, joint, effort, start, end):
        self.joint, self.effort, self.start, self.end = joint, effort, start, end


class _WrenchJob(object):
    __slots__ = ("link", "force", "torque", "point", "start", "duration")

    def __init__(self, link, force, torque, point, start, duration):
        self.link, self.force, self.torque, self.point = link, force, torque, point
        self.start, self.duration = start, duration


class ForceJobs(object):
    def __init__(self, world):
        self.world = world
        self._efforts, self._wrenches = [], []

    def start_and_duration(self, start, duration):
        """(start sim time, duration in s or None for 'until cleared'), Gazebo's semantics:
        a start in the past is now, a negative duration lasts until cleared."""
        now = self.world.time
        if start < now:
            start = now
        if duration < 0:
            return start, None
        return start, max(duration, self.world.time_step)

    def add_wrench(self, link, force, torque, point, start, duration):
        """force/torque in world axes, point in the link frame; active from ``start`` for
        ``duration`` seconds (None: until cleared)."""
        self._wrenches.append(_WrenchJob(link, force, torque, point, start, duration))
        self._activate_wrenches(self.world.time)

    def add_effort(self, joint, effort, start, end):
        self._efforts.append(_EffortJob(joint, effort, start, end))

    def clear_link(self, link):
        link.clear_wrenches()
        self._wrenches = [j for j in self._wrenches if j.link is not link]

    def clear_joint(self, joint):
        self._efforts = [j for j in self._efforts if j.joint is not joint]

    def drop_model(self, model):
        links = set(id(lk) for lk in model.links.values())
        self._wrenches = [j for j in self._wrenches if id(j.link) not in links]
        joints = set(id(j) for j in model.joints.values())
        self._efforts = [j for j in self._efforts if id(j.joint) not in joints]

    def reset(self):
        self._efforts, self._wrenches = [], []

    @property
    def idle(self):
        """True when no job is pending (the steps need nothing from here)."""
        return not self._efforts and not self._wrenches

    # ---- the before-step hook -------------------------------------------------------------------
    def activate_wrenches(self, t):
        if self._wrenches:
            self._activate_wrenches(t)

    def apply_efforts(self, t):
        if self._efforts:
            self._apply_efforts(t)

    def _activate_wrenches(self, t):
        keep = []
        for job in self._wrenches:
            if job.start <= t + 1e-12:
                duration = job.duration
                if duration is not None:
                    duration = max(self.world.time_step, duration - (t - job.start))
                try:
                    job.link.add_wrench(job.force, job.torque, reference_point=job.point, duration=duration)
                except ValueError as exc:  # dropped with one message, never retried
                    LOG.error("apply_body_wrench job dropped: %s", exc)
            else:
                keep.append(job)
        self._wrenches = keep

    def _apply_efforts(self, t):
        total = {}
        keep = []
        for job in self._efforts:
            if job.end is not None and t >= job.end - 1e-12:
                continue
            keep.append(job)
            if t + 1e-12 >= job.start:
                total[job.joint] = total.get(job.joint, 0.0) + job.effort
        self._efforts = keep
        failed = []
        for joint, effort in total.items():
            # Gazebo's SetForce adds up within a step: added to what a controller set this step
            try:
                joint.add_effort(effort)
            except ValueError as exc:  # a job that fails is dropped with one message
                LOG.error("apply_joint_effort job dropped: %s", exc)
                failed.append(joint)
        if failed:
            self._efforts = [j for j in self._efforts if j.joint not in failed]
