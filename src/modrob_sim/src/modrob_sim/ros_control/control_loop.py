"""gazebo_ros_control's update (read -> controllers -> write) in the World's step hooks, with its
due times (docs/plugins.md, "Due times"); pure, no rospy: the plugin (ros_control.plugin) and the
tests without ROS (gazebo_ros.testing) run the same.

An update runs in Python at the steps at which it has work: a controller's ``update_due`` (a
state message, a joint_state_controller sample, the end of a trajectory segment, a goal to
check), an adapter with a goal or command waiting, a gain changed. At the other steps the joints'
actuators (the World's) carry the last set-points. A controller that reports what its actuator
did in the update's step (``collect_due``) is collected in the after-step hook of that step."""
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
        self.manager.update(t, step, iteration=self.world.iterations)
        for a in adapters:
            a.after_update(t)

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
