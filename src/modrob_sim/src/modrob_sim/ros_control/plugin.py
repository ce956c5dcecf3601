"""The ``libgazebo_ros_control.so`` plugin of the /gazebo node (the ROS layer of the emulation).

For each model with ``<plugin filename="libgazebo_ros_control.so">`` it builds the simulated
hardware from the model's ``<transmission>`` tags and joints, reads the per-joint
``gazebo_ros_control/pid_gains``, and serves controller_manager's services under the robot
namespace. ``before_step(t, dt)`` runs in the simulation loop: queued goals in, read ->
controllers -> write, outputs published.

Threads (the plugin contract, docs/plugins.md): the controller manager and the adapters' table
belong to the simulation loop thread. The controller_manager service callbacks hand their work
to it with ``context.call`` and do only the ROS side (parameter reads, creating and shutting down
the controllers' topics) in their own thread.
"""
import rospy
from controller_manager_msgs.msg import ControllerState, HardwareInterfaceResources
from controller_manager_msgs.srv import (ListControllers, ListControllersResponse, ListControllerTypes,
                                         ListControllerTypesResponse, LoadController, LoadControllerResponse,
                                         ReloadControllerLibraries, ReloadControllerLibrariesResponse,
                                         SwitchController, SwitchControllerResponse, UnloadController,
                                         UnloadControllerResponse)

from modrob_sim.errors import LoopStoppedError, ModrobError
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin
from modrob_sim.ros_control import extensions
from modrob_sim.ros_control.control_loop import ControlLoop
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import BEST_EFFORT, ControllerManager
from modrob_sim.ros_control.params import Params, join
from modrob_sim.ros_control.plugin_config import DEFAULT_SIM_TYPE, PluginConfig
from modrob_sim.ros_control.ros_adapters import adapter_for
from modrob_sim.ros_control.ros_pid_reconfigure import PidReconfigure
from modrob_sim.ros_control.transmissions import parse_transmissions

FILENAME = "libgazebo_ros_control.so"
BASE_CLASS = "controller_interface::ControllerBase"

_LOG = {"debug": rospy.logdebug, "info": rospy.loginfo, "warn": rospy.logwarn, "error": rospy.logerr}


def _get_param(name):
    try:
        return rospy.get_param(name)
    except KeyError:
        return None


class GazeboRosControlPlugin(ModelPlugin):
    def load(self, model, spec, context):
        cfg = PluginConfig.from_element(spec.element, model.name,
                                        spec.robot_namespace or context.robot_namespace)
        self.config = cfg
        self.model_name = model.name
        self.namespace = cfg.robot_namespace
        make_hw = None
        if cfg.sim_type != DEFAULT_SIM_TYPE:
            make_hw, why = extensions.robot_sim_type(cfg.sim_type)
            if make_hw is None:
                rospy.logwarn("model '%s': robotSimType '%s' is not available here (%s); using %s"
                              % (model.name, cfg.sim_type, why, DEFAULT_SIM_TYPE))
        pid_ns, pid_values = None, None
        for ns in cfg.pid_gains_namespaces():
            values = _get_param(ns)
            if isinstance(values, dict) and values:
                pid_ns, pid_values = ns, values
                break
        transmissions = parse_transmissions(model.source_xml)
        pid_gains = Params(pid_values, pid_ns) if pid_ns else None

        def warn(text):
            rospy.logwarn("model '%s': %s" % (model.name, text))
        if make_hw is not None:
            self.hw = make_hw(self, model, transmissions, pid_gains, warn)
        else:
            self.hw = RobotHWSim(model.joints, transmissions, pid_gains, warn=warn, world=context.world)
        for note in self.hw.notes:
            rospy.loginfo("model '%s': %s" % (model.name, note))
        self.manager = ControllerManager(self.hw, self.namespace,
                                         log=lambda level, msg: _LOG[level]("%s: %s" % (self.namespace, msg)))
        self.manager.time_step = context.world.time_step
        self.adapters = {}      # controller name -> ROS adapter; changed only in the loop thread
        self.reconfigure = [PidReconfigure(res.pid, res.pid_source, on_change=lambda _g: context.wake())
                            for res in self.hw.pid_joints().values()]
        for name, res in self.hw.pid_joints().items():
            rospy.loginfo("model '%s': joint %s driven by the PID at %s (%s)"
                          % (model.name, name, res.pid_source, res.pid.gains))
        self.loop = ControlLoop(self.hw, self.manager, self.adapters, context.world, cfg.control_period)
        cm = join(self.namespace, "controller_manager")
        self.services = [
            rospy.Service(cm + "/list_controllers", ListControllers, self._list),
            rospy.Service(cm + "/list_controller_types", ListControllerTypes, self._types),
            rospy.Service(cm + "/load_controller", LoadController, self._load),
            rospy.Service(cm + "/unload_controller", UnloadController, self._unload),
            rospy.Service(cm + "/switch_controller", SwitchController, self._switch),
            rospy.Service(cm + "/reload_controller_libraries", ReloadControllerLibraries, self._reload),
        ]
        rospy.loginfo("model '%s': gazebo_ros_control in namespace %s, %d joints (%s)"
                      % (model.name, self.namespace, len(self.hw.order),
                         ", ".join("%s:%s" % (n, self.hw.joints[n].method) for n in self.hw.order)))

    # ---- simulation loop (ros_control.control_loop) ------------------------------------------
    def before_due(self):
        return self.loop.before_due()

    def before_step(self, t, dt):
        self.loop.before_step(t, dt)

    def after_due(self):
        return self.loop.after_due()

    def after_step(self, t, dt):
        self.loop.after_step(t, dt)

    def reset(self):
        self.loop.reset()
        now = self.context.world.time
        for adapter in self.adapters.values():
            adapter.reset(now)

    def shutdown(self):
        self.manager.stop_all()
        self.hw.remove_actuators()
        adapters, self.adapters = list(self.adapters.values()), {}
        for a in adapters:
            a.shutdown()
        for s in self.services:
            s.shutdown()
        for r in self.reconfigure:
            r.shutdown()

    # ---- controller_manager services (service threads; the work runs in the loop) ------------
    def _stopping_with_the_simulator(self, what, names):
        """A stop or unload that arrives while the simulator shuts down (a spawner taking its
        controllers down at the end of a launch): the controllers stop with the simulator, so the
        request is done - answered ok, logged at debug level only."""
        rospy.logdebug("%s: %s [%s]: the simulator is shutting down; the controllers stop with it"
                       % (self.namespace, what, ", ".join(names)))
        return True

    def _list(self, req):
        def read():
            return [ControllerState(name=c.name, state=c.state, type=c.TYPE, claimed_resources=[
                HardwareInterfaceResources(hardware_interface=iface, resources=list(joints))
                for iface, joints in c.claimed_resources]) for c in self.manager.list_controllers()]
        try:
            return ListControllersResponse(controller=self.context.call(read))
        except ModrobError as exc:
            rospy.logwarn("%s: list_controllers: %s" % (self.namespace, exc))
            return ListControllersResponse()

    def _types(self, req):
        types = self.manager.list_types()
        return ListControllerTypesResponse(types=types, base_classes=[BASE_CLASS] * len(types))

    def _load(self, req):
        name = req.name
        params = _get_param(join(self.namespace, name))
        try:
            controller = self.context.call(lambda: self.manager.load(name, params))
            try:
                adapter = adapter_for(self, controller)     # topics and services: this thread
            except Exception:
                self.context.call(lambda: self.manager.unload(name))
                raise
            self.context.call(lambda: self.adapters.__setitem__(name, adapter))
        except LoopStoppedError:
            rospy.logwarn("%s: cannot load controller '%s': the simulator is shutting down"
                          % (self.namespace, name))
            return LoadControllerResponse(ok=False)
        except ModrobError as exc:
            rospy.logerr("%s: %s" % (self.namespace, exc))
            return LoadControllerResponse(ok=False)
        rospy.loginfo("%s: loaded controller '%s' (%s)" % (self.namespace, name, controller.TYPE))
        return LoadControllerResponse(ok=True)

    def _unload(self, req):
        def unload():
            self.manager.unload(req.name)
            return self.adapters.pop(req.name, None)
        try:
            adapter = self.context.call(unload)
        except LoopStoppedError:
            return UnloadControllerResponse(ok=self._stopping_with_the_simulator("unload", [req.name]))
        except ModrobError as exc:
            rospy.logerr("%s: %s" % (self.namespace, exc))
            return UnloadControllerResponse(ok=False)
        if adapter is not None:
            adapter.shutdown()
        rospy.loginfo("%s: unloaded controller '%s'" % (self.namespace, req.name))
        return UnloadControllerResponse(ok=True)

    def _switch(self, req):
        try:
            ok, msg = self.context.call(lambda: self.manager.switch(
                list(req.start_controllers), list(req.stop_controllers), req.strictness))
        except LoopStoppedError:
            if req.start_controllers:
                rospy.logwarn("%s: cannot start [%s]: the simulator is shutting down"
                              % (self.namespace, ", ".join(req.start_controllers)))
                return SwitchControllerResponse(ok=False)
            return SwitchControllerResponse(ok=self._stopping_with_the_simulator(
                "stop", list(req.stop_controllers)))
        except ModrobError as exc:
            ok, msg = False, str(exc)
        if not ok:
            rospy.logerr("%s: switch_controller failed: %s" % (self.namespace, msg))
        elif req.start_controllers or req.stop_controllers:
            rospy.loginfo("%s: started [%s], stopped [%s]" % (self.namespace,
                                                              ", ".join(req.start_controllers),
                                                              ", ".join(req.stop_controllers)))
        return SwitchControllerResponse(ok=ok)

    def _reload(self, req):
        def kill_all():
            names = [c.name for c in self.manager.list_controllers()]
            if names and not req.force_kill:
                return names, None
            self.manager.switch([], [n for n in names if self.manager.get(n).state == "running"], BEST_EFFORT)
            adapters = [self.adapters.pop(n) for n in names if n in self.adapters]
            for n in names:
                self.manager.unload(n)
            return names, adapters
        try:
            names, adapters = self.context.call(kill_all)
        except ModrobError as exc:
            rospy.logerr("%s: reload_controller_libraries: %s" % (self.namespace, exc))
            return ReloadControllerLibrariesResponse(ok=False)
        if adapters is None:
            rospy.logerr("%s: Controller manager: Cannot reload controller libraries because there are "
                         "still %d controllers loaded (%s); call with force_kill: true"
                         % (self.namespace, len(names), ", ".join(names)))
            return ReloadControllerLibrariesResponse(ok=False)
        for a in adapters:
            a.shutdown()
        rospy.loginfo("%s: controller types reloaded (%d controllers were killed)" % (self.namespace,
                                                                                      len(names)))
        return ReloadControllerLibrariesResponse(ok=True)


register_plugin(FILENAME, GazeboRosControlPlugin)
