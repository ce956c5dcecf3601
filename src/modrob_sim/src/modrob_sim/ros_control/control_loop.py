"""gazebo_ros_control's update (read -> controllers -> write) in the World's step hooks, with its
due times (docs/plugins.md, "Due times"); pure, no rospy: the plugin (ros_control.plugin) and the
tests without ROS (gazebo_ros.testing) run the same.

An update runs in Python at the steps at which it has work: a controller's ``update_due`` (a state
message, a joint_state_controller sample, a trajectory whose pieces queued in the actuators run
low, a goal to check), an adapter with a goal or command waiting, a gain changed. At the other
steps the joints' actuators (the World's) carry the last set-points. An update updates the running
controllers for which the World would stop there (:func:`physics.due.stops_at` of their
``update_due``); the others are left out, as at the steps the World makes natively, unless the
controller says that its update has work at every update (``update_at_every_stop``) or an actuator
of its joints watches a goal's checks for it (a gripper goal, a trajectory goal's path tolerances:
the World ends a native stretch at the step at which one fires, a time no ``update_due`` gives). A
controller that reports what its actuator did in the update's step (``collect_due``) is collected
in the after-step hook of that step."""
from modrob_sim.physics.due import stops_at

INF = float("inf")


class ControlLoop(object):
    """``adapters``: controller name -> adapter (``before_update(t)``, ``after_update(t)``,
    ``waiting()``), the dict the plugin keeps; ``control_period`` (s) or None (every step)."""

    def __init__(self, hw, manager, adapters, world, control_period=None):
        self.hw = hw
        self.manager = manager
        self.adapters = adapters
        self.world = world
        self.control_period = control_period
        self.last_update = None
        #: True: every running controller updates at every update, due or not (gazebo_ros_control's
        #: update at every step, the reference of the tests that compare the two bit for bit)
        self.every_controller = False

    def _period(self):
        """The control period, or None when the controllers update at every step: no
        controlPeriod, or one no longer than the physics step (franka_description's 0.001 at 1 ms
        steps; gazebo_ros_control then updates before every step, one step apart). Only a longer
        period keeps an update in Python once per period."""
        period = self.control_period
        return None if period is None or period <= self.world.time_step + 1e-9 else period

    def before_due(self):
        period = self._period()
        if period is not None:
            return None if self.last_update is None else self.last_update + period - 1e-9
        if self.hw.needs_every_update:
            return None
        for a in self.adapters.values():
            if a.waiting():
                return None
        w = self.world
        t, it, dt = w.time, w.iterations, w.time_step
        due = INF
        for c in self.manager.controllers.values():
            if c.state == "running":
                d = c.update_due(t, it, dt)
                if d <= t:
                    return None
                if d < due:
                    due = d
        return due

    def before_step(self, t, dt):
        period = self._period()
        if period is not None and self.last_update is not None and t - self.last_update < period - 1e-9:
            return
        step = dt if self.last_update is None or period is None else t - self.last_update
        self.last_update = t
        adapters = list(self.adapters.values())
        for a in adapters:
            a.before_update(t)
        # with a control period every update runs whole, as gazebo_ros_control's does once per period
        due = None if period is not None or self.every_controller else self._due_controllers(t, dt)
        self.manager.update(t, step, iteration=self.world.iterations, controllers=due)
        for a in adapters:
            a.after_update(t)

    def _due_controllers(self, t, dt):
        """The running controllers whose update runs at the step starting at ``t`` (after the
        adapters handed over what waited: a goal makes its controller due)."""
        it = self.world.iterations
        return [c for c in self.manager.controllers.values()
                if c.state == "running" and (c.update_at_every_stop or stops_at(t, c.update_due(t, it, dt))
                                             or self._watched(c))]

    def _watched(self, c):
        """Whether an actuator of a joint of controller ``c`` watches a goal's checks or path
        tolerances (the World ends its native stretch at the step at which one fires, where the
        controller's update must run)."""
        joints = self.hw.joints
        for name in c.joint_names:
            res = joints.get(name)
            a = None if res is None else res.actuator
            if a is not None and (a.watching or a.band is not None):
                return True
        return False

    def after_due(self):
        for c in self.manager.controllers.values():
            if c.collect_due:
                return None
        return INF

    def after_step(self, t, dt):
        collected = False
        for c in self.manager.controllers.values():
            if c.collect_due:
                c.collect()
                collected = True
        if collected:
            for a in list(self.adapters.values()):
                a.after_update(t)

    def reset(self):
        """reset_simulation / reset_world: hold where the joints are, the running controllers
        started again (at time 0)."""
        self.last_update = None
        self.manager.time = 0.0
        self.hw.reset_commands()
        for c in self.manager.list_controllers():
            if c.state == "running":
                c.starting(0.0)
