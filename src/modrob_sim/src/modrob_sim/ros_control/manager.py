"""controller_manager's semantics (ros_control Noetic), pure: load / unload / switch / list,
resource conflicts, and ``update(t, dt)`` (read -> controllers -> write) at simulated time.

Controller states: 'initialized' after load, 'running' after start, 'stopped' after stop.
Switches take effect at once (also while the simulation is paused), not at the next update.
"""
from modrob_sim.errors import ControllerError
from modrob_sim.ros_control import extensions, gain_check
from modrob_sim.ros_control.controllers import CONTROLLER_TYPES
from modrob_sim.ros_control.params import Params, join

BEST_EFFORT = 1
STRICT = 2


class ControllerManager(object):
    def __init__(self, hw, namespace="/", types=None, log=None):
        """``hw``: RobotHWSim. ``namespace``: where controller parameters live.
        ``log(level, msg)``: level in 'debug', 'info', 'warn', 'error'."""
        self.hw = hw
        self.namespace = namespace
        self.types = dict(types or CONTROLLER_TYPES)
        self.controllers = {}          # name -> Controller, in load order
        self.log = log or (lambda level, msg: None)
        self.time = 0.0
        #: the physics step (s); when set, loading a controller warns about gains that cannot run
        self.time_step = None

    # -- queries ---------------------------------------------------------------------------
    def list_types(self):
        return sorted(set(self.types) | set(extensions.registered_controller_types()))

    def list_controllers(self):
        return list(self.controllers.values())

    def get(self, name):
        return self.controllers.get(name)

    # -- load / unload ---------------------------------------------------------------------
    def load(self, name, params_values):
        """Build controller ``name`` from its parameter namespace (a dict, or None when the
        namespace does not exist). Returns the controller; ControllerError says what is wrong."""
        ns = join(self.namespace, name)
        if name in self.controllers:
            raise ControllerError("A controller named '%s' was already loaded inside the controller "
                                  "manager" % name)
        if not isinstance(params_values, dict) or "type" not in params_values:
            raise ControllerError("Could not load controller '%s' because the type was not specified. "
                                  "Did you load "
                                  "the controller configuration on the parameter server (namespace: '%s')?"
                                  % (name, ns))
        type_ = params_values["type"]
        if not isinstance(type_, str):
            raise ControllerError("Could not load controller '%s' because its type is %r, not a type name "
                                  "(parameter %s/type, e.g. effort_controllers/JointPositionController)"
                                  % (name, type_, ns))
        cls = self.types.get(type_) or extensions.controller_type(type_)
        if cls is None:
            raise ControllerError("Could not load controller '%s' because controller type '%s' does not "
                                  "exist "
                                  "(parameter %s/type). Known types: %s"
                                  % (name, type_, ns, ", ".join(self.list_types())))
        controller = cls(name, self.hw, Params(params_values, ns))
        self.controllers[name] = controller
        if self.time_step:
            for joint, gain, k, limit, inertia in gain_check.unstable_gains(controller, self.time_step):
                self.log("warn", gain_check.message(name, joint, gain, k, limit, inertia, self.time_step))
        return controller

    def unload(self, name):
        c = self.controllers.get(name)
        if c is None:
            raise ControllerError("Could not unload controller with name '%s' because no controller "
                                  "with this "
                                  "name exists (loaded: %s)" % (name, ", ".join(self.controllers) or "none"))
        if c.state == "running":
            raise ControllerError("Could not unload controller with name '%s' because it is still running; "
                                  "stop it first (switch_controller)" % name)
        del self.controllers[name]
        return c

    # -- switch ----------------------------------------------------------------------------
    def switch(self, start, stop, strictness=STRICT):
        """Stop ``stop`` and start ``start`` together. Returns (ok, message)."""
        if strictness not in (BEST_EFFORT, STRICT):
            self.log("warn", "Controller Manager: To switch controllers you need to specify a "
                             "strictness level of "
                     "controller_manager_msgs::SwitchController::STRICT (2) or ::BEST_EFFORT (1). "
                     "Defaulting to "
                     "::BEST_EFFORT.")
            strictness = BEST_EFFORT
        problems = []
        to_stop, to_start = [], []
        for name in stop:
            c = self.controllers.get(name)
            if c is None:
                problems.append("Could not stop controller with name '%s' because no controller with "
                                "this name "
                                "exists" % name)
            elif c.state != "running":
                problems.append("Could not stop controller '%s' since it is not running" % name)
            elif name not in to_stop:
                to_stop.append(name)
        for name in start:
            c = self.controllers.get(name)
            if c is None:
                problems.append("Could not start controller with name '%s' because no controller with "
                                "this name "
                                "exists" % name)
            elif c.state == "running" and name not in to_stop:
                problems.append("Could not start controller '%s' since it is already running" % name)
            elif name not in to_start:
                to_start.append(name)
        if problems and strictness == STRICT:
            return False, "; ".join(problems)
        for p in problems:
            self.log("debug", p)
        running = [n for n, c in self.controllers.items()
                   if c.state == "running" and n not in to_stop] + to_start
        claims = {}     # joint -> (controller, interface): one claim per joint, whatever the interface
        for n in running:
            for iface, joints in self.controllers[n].claimed_resources:
                for j in joints:
                    if j in claims and claims[j][0] != n:
                        other, other_iface = claims[j]
                        return False, ("Resource conflict for resource '%s' between controllers '%s' (%s) "
                                       "and '%s' (%s): stop one of them in the same switch"
                                       % (j, other, other_iface, n, iface))
                    claims[j] = (n, iface)
        # as controller_manager, which switches at the start of its next update: at the World's
        # time now (the last update may lie several steps back when updates run only when due)
        t = self.hw.world.time if self.hw.world is not None else self.time
        # as controller_manager: the hardware switches interfaces first, then stop, then start
        self.hw.do_switch([self.controllers[n] for n in to_start], [self.controllers[n] for n in to_stop])
        for n in to_stop:
            c = self.controllers[n]
            c.stopping(t)
            c.state = "stopped"
        self.hw.read()
        for n in to_start:
            c = self.controllers[n]
            c.starting(t)
            c.state = "running"
        return True, "; ".join(problems)

    def stop_all(self):
        running = [n for n, c in self.controllers.items() if c.state == "running"]
        if running:
            self.switch([], running, BEST_EFFORT)
        return running

    # -- loop ------------------------------------------------------------------------------
    def update(self, t, dt, iteration=None, controllers=None):
        """read -> update running controllers -> write, at simulated time ``t``; ``iteration``:
        the index of the physics step (the World's count: the steps between two updates in
        Python count too), else one more than the last update's. ``controllers``: the running
        controllers to update, in the manager's order (None: every running one)."""
        self.time = t
        self.hw.iteration = self.hw.iteration + 1 if iteration is None else iteration
        self.hw.read()
        for c in self.controllers.values() if controllers is None else controllers:
            if c.state == "running":
                c.update(t, dt)
        self.hw.write(dt, t)
        if self.hw.world is None:       # write ran the actuators: what they did is known now
            for c in self.controllers.values():
                if c.collect_due:
                    c.collect()
