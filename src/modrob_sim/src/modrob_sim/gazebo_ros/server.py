"""The /gazebo node: Gazebo's ROS interface (gazebo_ros_api_plugin) on top of modrob_sim.physics.

One thread (:class:`~modrob_sim.gazebo_ros.sim_loop.SimulationLoop`) owns the World: it steps it,
runs the plugins in the World's before-step hook (read -> controllers.update(t, dt) -> write),
publishes from the after-step hook (decimated), and runs every request that ROS callbacks hand to
it between two steps. Service callbacks never touch the World themselves.
"""
import logging
import math
import sys
import time
import traceback

import rospy
from gazebo_msgs import msg as gzm
from gazebo_msgs import srv as gzs
from geometry_msgs.msg import Pose, Twist, Vector3
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String
from std_srvs.srv import Empty, EmptyResponse
from visualization_msgs.msg import MarkerArray

from modrob_msgs.srv import StepSimulation, StepSimulationResponse
from modrob_sim.errors import ModelError, ModrobError
from modrob_sim.camera.scene import ScenePublisher
from modrob_sim.gazebo_ros import description, markers, plugins
from modrob_sim.gazebo_ros import transforms as tf
from modrob_sim.gazebo_ros.plugin_host import PluginHost
from modrob_sim.gazebo_ros.publishing import PublishQueue, ros_advertiser
from modrob_sim.gazebo_ros.resources import ResourceResolver
from modrob_sim.gazebo_ros.sim_loop import SimulationLoop
from modrob_sim.gazebo_ros.world_file import find_world, world_physics

NO_LINK = "link [%s] does not exist; use the scoped name model::link"
WORLD_FRAMES = ("", "world", "map", "/map", "/world")

#: physics_params keys of the core <-> fields of gazebo_msgs/ODEPhysics
ODE_FIELDS = (("iters", "sor_pgs_iters"), ("sor", "sor_pgs_w"), ("cfm", "cfm"), ("erp", "erp"),
              ("contact_max_correcting_vel", "contact_max_correcting_vel"),
              ("contact_surface_layer", "contact_surface_layer"), ("max_contacts", "max_contacts"))

JOINT_TYPE = {"revolute": gzs.GetJointPropertiesResponse.REVOLUTE,
              "continuous": gzs.GetJointPropertiesResponse.CONTINUOUS,
              "prismatic": gzs.GetJointPropertiesResponse.PRISMATIC,
              "fixed": gzs.GetJointPropertiesResponse.FIXED,
              "floating": gzs.GetJointPropertiesResponse.BALL,
              "planar": gzs.GetJointPropertiesResponse.UNIVERSAL}


class Params(object):
    """The node's parameters (see docs/simulator.md)."""

    def __init__(self, time_step=None, real_time_factor=None, paused=False, seed=0, world_name="",
                 pub_clock_frequency=1000.0, publish_rate=100.0, marker_rate=10.0, marker_models="props",
                 rtf_log_period=5.0, plugin_modules=(), gravity=None):
        self.time_step = time_step
        self.real_time_factor = real_time_factor
        self.paused = paused
        self.seed = seed
        self.world_name = world_name
        self.pub_clock_frequency = pub_clock_frequency
        self.publish_rate = publish_rate
        self.marker_rate = marker_rate
        self.marker_models = marker_models
        self.rtf_log_period = rtf_log_period
        self.plugin_modules = list(plugin_modules)
        self.gravity = gravity

    @classmethod
    def from_ros(cls, argv=()):
        """Read ``~params`` and gzserver's arguments in ``argv`` (``-u`` start paused, ``--verbose``,
        ``-e ode``, a world file). An unset time_step / real_time_factor comes from the world
        file's <physics> (else 0.001 s and 1.0), as Gazebo takes them from the world."""
        def opt(name):
            return rospy.get_param("~" + name) if rospy.has_param("~" + name) else None
        args = parse_server_args(argv)
        engine = str(rospy.get_param("~physics", args["physics"] or "ode"))
        if engine != "ode":
            rospy.logwarn("physics engine '%s' requested; this simulator has only ode: using ode" % engine)
        return cls(time_step=opt("time_step"), real_time_factor=opt("real_time_factor"),
                   paused=bool(rospy.get_param("~paused", False)) or args["paused"],
                   seed=int(rospy.get_param("~seed", 0)),
                   world_name=str(rospy.get_param("~world_name", args["world"] or "")),
                   pub_clock_frequency=float(rospy.get_param("~pub_clock_frequency", 1000.0)),
                   publish_rate=float(rospy.get_param("~publish_rate", 100.0)),
                   marker_rate=float(rospy.get_param("~marker_rate", 10.0)),
                   marker_models=str(rospy.get_param("~marker_models", "props")),
                   rtf_log_period=float(rospy.get_param("~rtf_log_period", 5.0)),
                   plugin_modules=_as_list(rospy.get_param("~plugin_modules", [])))


def _as_list(value):
    """A parameter that should be a list: "a, b" or "a" become ["a", "b"] / ["a"]."""
    if isinstance(value, str):
        return [v.strip() for v in value.replace(",", " ").split() if v.strip()]
    return list(value or [])


def parse_server_args(argv):
    """gzserver's command line as gazebo_ros's launch files pass it: -u, --verbose, -e ENGINE,
    a world file; other flags are ignored (they are Gazebo's, without meaning here)."""
    out = {"paused": False, "verbose": False, "physics": None, "world": None, "ignored": []}
    it = iter(argv)
    for a in it:
        if a in ("-u", "--pause"):
            out["paused"] = True
        elif a == "--verbose":
            out["verbose"] = True
        elif a in ("-e", "--physics"):
            out["physics"] = next(it, None)
        elif a.startswith("-"):
            out["ignored"].append(a)
        elif a:
            out["world"] = a
    return out


class RequestError(ModrobError):
    """A request that cannot be served; the text is the service's status_message."""


# ---- message <-> tuple conversion --------------------------------------------------------------
def pose_from_msg(p, what):
    pose = ((p.position.x, p.position.y, p.position.z),
            (p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w))
    if not tf.is_finite(pose):
        raise RequestError("%s has a NaN or infinite value: %s" % (what, pose))
    return (pose[0], tf.quat_normalize(pose[1]))


def twist_from_msg(t, what):
    twist = ((t.linear.x, t.linear.y, t.linear.z), (t.angular.x, t.angular.y, t.angular.z))
    if not tf.is_finite(twist):
        raise RequestError("%s has a NaN or infinite value: %s" % (what, twist))
    return twist


def pose_to_msg(pose, msg=None):
    msg = msg or Pose()
    (msg.position.x, msg.position.y, msg.position.z) = pose[0]
    (msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w) = pose[1]
    return msg


def twist_to_msg(twist, msg=None):
    msg = msg or Twist()
    (msg.linear.x, msg.linear.y, msg.linear.z) = twist[0]
    (msg.angular.x, msg.angular.y, msg.angular.z) = twist[1]
    return msg


def ros_time(t):
    secs = int(math.floor(t))
    nsecs = int(round((t - secs) * 1e9))
    if nsecs >= 1000000000:
        secs, nsecs = secs + 1, nsecs - 1000000000
    return rospy.Time(secs, nsecs)


class _Status(object):
    """success / status_message holder for services whose response has neither (std_srvs/Empty)."""
    success = False
    status_message = ""


class _EffortJob(object):
    __slots__ = ("joint", "effort", "start", "end")

    def __init__(self, joint, effort, start, end):
        self.joint, self.effort, self.start, self.end = joint, effort, start, end


class _WrenchJob(object):
    __slots__ = ("link", "force", "torque", "point", "start", "duration")

    def __init__(self, link, force, torque, point, start, duration):
        self.link, self.force, self.torque, self.point = link, force, torque, point
        self.start, self.duration = start, duration


class GazeboRosNode(object):
    """Gazebo's ROS API for a physics World. ``world_factory(time_step, gravity, seed, resolver)``
    builds the World (modrob_sim.physics.World by default)."""

    def __init__(self, params, world_factory=None, node_name=None):
        self.params = params
        self.node_name = node_name or rospy.get_name()
        self.resolve = ResourceResolver()
        self._effort_jobs, self._wrench_jobs = [], []
        self._spawn_ns = {}
        self._guard_hint = {}
        self._seq = 0

        world_text, physics = None, {}
        if params.world_name:
            path = find_world(params.world_name, self.resolve)
            with open(path) as f:
                world_text = f.read()
            physics = world_physics(world_text)
            rospy.loginfo("world file %s" % path)
        time_step = params.time_step if params.time_step is not None else physics.get("time_step", 0.001)
        rtf = params.real_time_factor
        if rtf is None:
            rtf = physics.get("real_time_factor", 1.0)
            if physics.get("real_time_update_rate", 1.0) <= 0:
                rtf = 0.0   # Gazebo: update rate 0 = as fast as possible
        gravity = params.gravity or physics.get("gravity", (0.0, 0.0, -9.81))
        if not (time_step > 0 and math.isfinite(time_step)):
            raise ModelError("~time_step must be a positive number of seconds, got %r" % time_step)
        if world_factory is None:
            from modrob_sim.physics import World

            def world_factory(time_step, gravity, seed, resolver):
                return World(time_step=time_step, gravity=gravity, seed=seed, resource_resolver=resolver)
        self.world = world_factory(float(time_step), tuple(gravity), int(params.seed), self.resolve)
        forward_python_logging("modrob_sim")
        self._own_sim_time = take_over_sim_time()
        self._hook = self.world.add_step_hook(before=self._before_step, after=self._after_step)

        plugins.import_plugin_modules(plugins.PLUGIN_MODULES + list(params.plugin_modules),
                                      on_error=self._plugin_module_failed)

        # publishers (before any model exists, so the first states go out)
        # latched: a node that starts while the simulation is paused still learns the time
        self._clock_pub = rospy.Publisher("/clock", Clock, queue_size=10, latch=True)
        self._clock_msg = Clock()
        self._model_states_pub = rospy.Publisher("~model_states", gzm.ModelStates, queue_size=1)
        self._link_states_pub = rospy.Publisher("~link_states", gzm.LinkStates, queue_size=1)
        self._perf_pub = rospy.Publisher("~performance_metrics", gzm.PerformanceMetrics, queue_size=1)
        self._guard_pub = rospy.Publisher("~guard_events", String, queue_size=20)
        self._marker_pub = rospy.Publisher("~world_markers", MarkerArray, queue_size=1, latch=True)
        self._markers = markers.WorldMarkers(self.world, params.marker_models)
        # every model's visuals + per-link tf for RViz and the camera renderer (modrob_sim.camera)
        self._scene = ScenePublisher.for_world(self.world, float(rospy.get_param("~scene_rate", 30.0)))

        self._clock_period = 1.0 / params.pub_clock_frequency if params.pub_clock_frequency > 0 else 0.0
        self._last_clock_wall = -1e9
        self._state_period = 1.0 / params.publish_rate if params.publish_rate > 0 else 0.0
        self._next_state_t = 0.0
        self._marker_period = 1.0 / params.marker_rate if params.marker_rate > 0 else 0.0
        self._next_marker_t = 0.0
        self._last_rtf_log = time.monotonic()

        self.loop = SimulationLoop(self.world, real_time_factor=rtf, paused=params.paused,
                                   on_rtf=self._on_rtf, on_error=self._on_step_error)
        self._publish_queue = PublishQueue()
        self.plugins = PluginHost(self.world, self.node_name, self.resolve, call=self.loop.call,
                                  advertise=ros_advertiser(self._publish_queue))
        if world_text is not None:
            try:
                for m in self.world.add_sdf(world_text):
                    self.plugins.load(m, "")
            except ModrobError as exc:
                raise ModelError("world file %s: %s" % (params.world_name, exc))
            # the core applies the world's <physics>; explicit ~time_step / gravity win over it
            self.world.time_step = float(time_step)
            self.world.gravity = tuple(gravity)
        self._publish_markers(force=True)
        self._publish_clock(force=True)
        self._advertise()
        rospy.loginfo("%s: time step %g s, real-time factor %s, %s, %d models" % (
            self.node_name, time_step, "unlimited" if rtf <= 0 else "%g" % rtf,
            "paused" if params.paused else "running", len(self.world.models)))

    # ---- life cycle ----------------------------------------------------------------------------
    def start(self):
        self.loop.start()

    def shutdown(self):
        self.loop.stop()
        self.plugins.shutdown()
        self._publish_queue.stop()

    def _advertise(self):
        S = rospy.Service
        self._services = [
            S("~spawn_urdf_model", gzs.SpawnModel, lambda r: self._spawn(r, "urdf")),
            S("~spawn_sdf_model", gzs.SpawnModel, lambda r: self._spawn(r, "sdf")),
            S("~delete_model", gzs.DeleteModel, self._delete_model),
            S("~get_model_state", gzs.GetModelState, self._get_model_state),
            S("~set_model_state", gzs.SetModelState, self._set_model_state_srv),
            S("~set_model_configuration", gzs.SetModelConfiguration, self._set_model_configuration),
            S("~get_link_state", gzs.GetLinkState, self._get_link_state),
            S("~set_link_state", gzs.SetLinkState, self._set_link_state_srv),
            S("~get_world_properties", gzs.GetWorldProperties, self._get_world_properties),
            S("~get_model_properties", gzs.GetModelProperties, self._get_model_properties),
            S("~get_joint_properties", gzs.GetJointProperties, self._get_joint_properties),
            S("~get_link_properties", gzs.GetLinkProperties, self._get_link_properties),
            S("~set_link_properties", gzs.SetLinkProperties, self._set_link_properties),
            S("~apply_body_wrench", gzs.ApplyBodyWrench, self._apply_body_wrench),
            S("~apply_joint_effort", gzs.ApplyJointEffort, self._apply_joint_effort),
            S("~clear_body_wrenches", gzs.BodyRequest, self._clear_body_wrenches),
            S("~clear_joint_forces", gzs.JointRequest, self._clear_joint_forces),
            S("~pause_physics", Empty, self._pause),
            S("~unpause_physics", Empty, self._unpause),
            S("~reset_simulation", Empty, self._reset_simulation),
            S("~reset_world", Empty, self._reset_world),
            S("~get_physics_properties", gzs.GetPhysicsProperties, self._get_physics_properties),
            S("~set_physics_properties", gzs.SetPhysicsProperties, self._set_physics_properties),
            S("~step", StepSimulation, self._step),
            # Gazebo offers these too; this simulator models no lights and no ODE joint tuning:
            # they answer success: false with the reason instead of leaving callers waiting
            S("~delete_light", gzs.DeleteLight, lambda r: self._unsupported(
                gzs.DeleteLightResponse(), "DeleteLight", "light [%s]" % r.light_name,
                "lights are not simulated")),
            S("~get_light_properties", gzs.GetLightProperties, lambda r: self._unsupported(
                gzs.GetLightPropertiesResponse(), "GetLightProperties", "light [%s]" % r.light_name,
                "lights are not simulated (RViz lights the scene itself)")),
            S("~set_light_properties", gzs.SetLightProperties, lambda r: self._unsupported(
                gzs.SetLightPropertiesResponse(), "SetLightProperties", "light [%s]" % r.light_name,
                "lights are not simulated (RViz lights the scene itself)")),
            S("~set_joint_properties", gzs.SetJointProperties, lambda r: self._unsupported(
                gzs.SetJointPropertiesResponse(), "SetJointProperties", "joint [%s]" % r.joint_name,
                "ODE joint parameters cannot be changed at run time; set <dynamics> and <limit> in the "
                "URDF and spawn the model again")),
        ]
        self._subs = [
            rospy.Subscriber("~set_model_state", gzm.ModelState, self._set_model_state_topic, queue_size=50),
            rospy.Subscriber("~set_link_state", gzm.LinkState, self._set_link_state_topic, queue_size=50),
        ]

    # ---- the loop's hooks (loop thread) -----------------------------------------------------
    def _before_step(self, t, dt):
        if self._own_sim_time:
            rospy.rostime._set_rostime(ros_time(t))
        if self._wrench_jobs:
            self._activate_wrenches(t)
        self.plugins.before_step(t, dt)
        if self._effort_jobs:
            self._apply_efforts(t, dt)

    def _after_step(self, t, dt):
        self.plugins.after_step(t, dt)
        now_t = self.world.time
        if self._clock_period <= 0.0:
            self._publish_clock()
        else:
            wall = time.monotonic()
            if wall - self._last_clock_wall >= self._clock_period:
                self._last_clock_wall = wall
                self._publish_clock()
        if now_t + 1e-12 >= self._next_state_t:
            self._next_state_t = now_t + self._state_period if self._state_period > 0 else 0.0
            self._publish_states()
            self._report_guard_events()
        if self._marker_period > 0.0 and now_t + 1e-12 >= self._next_marker_t:
            self._next_marker_t = now_t + self._marker_period
            self._publish_markers()
        self._scene.after_step(now_t)

    def _publish_clock(self, force=False):
        t = self.world.time
        c = self._clock_msg.clock
        c.secs = int(t)
        c.nsecs = int(round((t - c.secs) * 1e9))
        if c.nsecs >= 1000000000:
            c.secs += 1
            c.nsecs -= 1000000000
        self._clock_pub.publish(self._clock_msg)

    def _publish_states(self):
        world = self.world
        if self._model_states_pub.get_num_connections() > 0:
            ms = gzm.ModelStates()
            for name, model in world.models.items():
                ms.name.append(name)
                ms.pose.append(pose_to_msg(model.pose))
                ms.twist.append(twist_to_msg(model.twist))
            self._model_states_pub.publish(ms)
        if self._link_states_pub.get_num_connections() > 0:
            ls = gzm.LinkStates()
            for mname, model in world.models.items():
                for lname, link in model.links.items():
                    ls.name.append("%s::%s" % (mname, lname))
                    ls.pose.append(pose_to_msg(link.pose))
                    ls.twist.append(twist_to_msg(link.twist))
            self._link_states_pub.publish(ls)

    def _publish_markers(self, force=False):
        arr = self._markers.update(force=force)
        if arr is not None:
            self._marker_pub.publish(arr)

    def _report_guard_events(self):
        """Publish every guard event; the core logs each one, the node adds a hint at most every
        5 s per model (a model that keeps blowing up would flood the log otherwise)."""
        for ev in self.world.pop_events():
            self._guard_pub.publish(String(data="model=%s link=%s time=%.6f reason=%s"
                                           % (ev.model, ev.link, ev.time, ev.reason)))
            wall = time.monotonic()
            if wall - self._guard_hint.get(ev.model, -1e9) >= 5.0:
                self._guard_hint[ev.model] = wall
                rospy.logerr("model '%s' (link '%s') blew up and was restored: check its controller gains, "
                             "commanded efforts, link masses/inertias and the time step; events on %s"
                             % (ev.model, ev.link, self._guard_pub.resolved_name))

    def _on_rtf(self, rtf, sim_time):
        msg = gzm.PerformanceMetrics()
        msg.header.stamp = ros_time(sim_time)
        msg.real_time_factor = rtf
        self._perf_pub.publish(msg)
        wall = time.monotonic()
        if self.params.rtf_log_period > 0 and wall - self._last_rtf_log >= self.params.rtf_log_period:
            self._last_rtf_log = wall
            rospy.loginfo("sim time %.2f s, real-time factor %.2f%s" % (
                sim_time, rtf, " (paused)" if self.loop.paused else ""))

    def _on_step_error(self, exc):
        rospy.logerr("physics step failed, physics paused (call /gazebo/unpause_physics to go on): %s: %s\n%s"
                     % (type(exc).__name__, exc, traceback.format_exc()))

    # ---- plugins --------------------------------------------------------------------------------
    def _plugin_module_failed(self, module, text):
        if text.startswith("ModuleNotFoundError") and ("'%s'" % module.rsplit(".", 1)[0]) in text or \
                ("'%s'" % module) in text:
            rospy.loginfo("plugin module %s is not available (%s): its plugins will be ignored"
                          % (module, text))
        else:
            rospy.logerr("plugin module %s failed to import, its plugins will be ignored: %s"
                         % (module, text))

    # ---- lookup (loop thread) -----------------------------------------------------------------
    def _model(self, name, what="model"):
        m = self.world.models.get(name)
        if m is None:
            raise RequestError("%s [%s] does not exist (models: %s)"
                               % (what, name, ", ".join(self.world.models) or "none"))
        return m

    def _find_link(self, name):
        """A link by scoped name model::link, or by a link name unique in the world; None if none."""
        if "::" in name:
            mname, lname = name.rsplit("::", 1)
            m = self.world.models.get(mname)
            return m.links.get(lname) if m is not None else None
        found = [m.links[name] for m in self.world.models.values() if name in m.links]
        return found[0] if len(found) == 1 else None

    def _find_joint(self, name):
        if "::" in name:
            mname, jname = name.rsplit("::", 1)
            m = self.world.models.get(mname)
            return m.joints.get(jname) if m is not None else None
        for m in self.world.models.values():
            if name in m.joints:
                return m.joints[name]
        return None

    def _frame(self, name, field="reference_frame"):
        """(pose, twist) of a reference frame, or None for the world; RequestError when unknown."""
        if name in WORLD_FRAMES:
            return None
        m = self.world.models.get(name)
        if m is not None:
            return m.pose, m.twist
        link = self._find_link(name)
        if link is not None:
            return link.pose, link.twist
        raise RequestError("%s [%s] is neither a model nor a link; use \"world\", a model name or a scoped "
                           "link name model::link" % (field, name))

    def _run(self, fn, response, name, timeout=120.0):
        """Run fn() in the loop; fill response.success / status_message. fn returns a message."""
        try:
            text = self.loop.call(fn, timeout=timeout)
            response.success = True
            response.status_message = "%s: %s" % (name, text)
        except ModrobError as exc:
            response.success = False
            response.status_message = "%s: %s" % (name, exc)
            rospy.logwarn(response.status_message)
        except ValueError as exc:
            response.success = False
            response.status_message = "%s: %s" % (name, exc)
            rospy.logwarn(response.status_message)
        return response

    @staticmethod
    def _unsupported(resp, name, what, why):
        resp.success = False
        resp.status_message = "%s: %s: not supported by this simulator: %s" % (name, what, why)
        rospy.logwarn(resp.status_message)
        return resp

    # ---- spawn / delete -----------------------------------------------------------------------
    def _spawn(self, req, service_kind):
        name = req.model_name.strip()
        xml = req.model_xml
        resp = gzs.SpawnModelResponse()

        def do():
            if not name:
                raise RequestError("model_name is empty: give the model a name")
            if name in self.world.models:
                raise RequestError("model name [%s] already exists: delete it first (/gazebo/delete_model) "
                                   "or choose another name" % name)
            if not xml.strip():
                raise RequestError("model_xml of [%s] is empty (did the robot_description parameter "
                                   "load?)" % name)
            kind = description.xml_kind(xml)
            if kind is None:
                try:
                    import xml.etree.ElementTree as ET
                    ET.fromstring(xml)
                    raise RequestError("model_xml of [%s] is neither URDF (<robot>) nor SDF (<sdf>, "
                                       "<model>)" % name)
                except ET.ParseError as exc:
                    raise RequestError("model_xml of [%s] is not valid XML: %s" % (name, exc))
            pose = pose_from_msg(req.initial_pose, "initial_pose")
            frame = self._frame(req.reference_frame)
            if frame is not None:
                pose = tf.compose(frame[0], pose)
            ns = req.robot_namespace
            try:
                if kind == "urdf":
                    models = [self.world.add_urdf(name, xml, pose=pose, robot_namespace=ns)]
                else:
                    models = self.world.add_sdf(xml, name=name, pose=pose)
            except ModrobError as exc:
                raise RequestError("could not spawn [%s]: %s" % (name, exc))
            for m in models:
                self._spawn_ns[m.name] = ns
                self.plugins.load(m, ns)
            self._publish_markers(force=True)
            return "Successfully spawned entity [%s]" % ", ".join(m.name for m in models)
        if service_kind != description.xml_kind(xml) and description.xml_kind(xml) is not None:
            rospy.loginfo("spawn_%s_model got %s text for [%s]: spawning it as %s" % (
                service_kind, description.xml_kind(xml).upper(), name, description.xml_kind(xml).upper()))
        return self._run(do, resp, "SpawnModel")

    def _delete_model(self, req):
        def do():
            self._model(req.model_name)
            self.plugins.unload(req.model_name)
            links = set(id(lk) for lk in self.world.models[req.model_name].links.values())
            self._wrench_jobs = [j for j in self._wrench_jobs if id(j.link) not in links]
            joints = set(id(j) for j in self.world.models[req.model_name].joints.values())
            self._effort_jobs = [j for j in self._effort_jobs if id(j.joint) not in joints]
            self.world.remove_model(req.model_name)
            self._spawn_ns.pop(req.model_name, None)
            self._publish_markers(force=True)
            return "successfully deleted model [%s]" % req.model_name
        return self._run(do, gzs.DeleteModelResponse(), "DeleteModel")

    # ---- states -----------------------------------------------------------------------------------
    def _get_model_state(self, req):
        resp = gzs.GetModelStateResponse()

        def do():
            m = self._model(req.model_name)
            pose, twist = m.pose, m.twist
            frame = self._frame(req.relative_entity_name, "relative_entity_name")
            if frame is not None:
                pose = tf.relative(frame[0], pose)
                twist = tf.twist_in_frame(frame[0], frame[1], twist)
            self._seq += 1
            resp.header.seq = self._seq
            resp.header.stamp = ros_time(self.world.time)
            resp.header.frame_id = req.relative_entity_name
            pose_to_msg(pose, resp.pose)
            twist_to_msg(twist, resp.twist)
            return "got properties"
        return self._run(do, resp, "GetModelState")

    def _apply_model_state(self, state):
        m = self._model(state.model_name)
        pose = pose_from_msg(state.pose, "model_state.pose")
        twist = twist_from_msg(state.twist, "model_state.twist")
        frame = self._frame(state.reference_frame)
        if frame is not None:
            pose = tf.compose(frame[0], pose)
            twist = tf.twist_to_world(frame[0], twist)
        m.set_pose(pose)
        m.set_twist(twist)
        return "set model state done"

    def _set_model_state_srv(self, req):
        return self._run(lambda: self._apply_model_state(req.model_state), gzs.SetModelStateResponse(),
                         "SetModelState")

    def _set_model_state_topic(self, msg):
        self._post(lambda: self._apply_model_state(msg), "/gazebo/set_model_state")

    def _apply_link_state(self, state):
        link = self._find_link(state.link_name)
        if link is None:
            raise RequestError(NO_LINK % state.link_name)
        pose = pose_from_msg(state.pose, "link_state.pose")
        twist = twist_from_msg(state.twist, "link_state.twist")
        frame = self._frame(state.reference_frame)
        if frame is not None:
            pose = tf.compose(frame[0], pose)
            twist = tf.twist_to_world(frame[0], twist)
        link.set_pose(pose)
        link.set_twist(twist)
        return "set link state done"

    def _set_link_state_srv(self, req):
        return self._run(lambda: self._apply_link_state(req.link_state), gzs.SetLinkStateResponse(),
                         "SetLinkState")

    def _set_link_state_topic(self, msg):
        self._post(lambda: self._apply_link_state(msg), "/gazebo/set_link_state")

    def _post(self, fn, what):
        def job():
            try:
                fn()
            except (ModrobError, ValueError) as exc:
                rospy.logwarn("%s: %s" % (what, exc))
        try:
            self.loop.call(job)
        except ModrobError as exc:
            rospy.logwarn("%s: %s" % (what, exc))

    def _get_link_state(self, req):
        resp = gzs.GetLinkStateResponse()

        def do():
            link = self._find_link(req.link_name)
            if link is None:
                raise RequestError(NO_LINK % req.link_name)
            pose, twist = link.pose, link.twist
            frame = self._frame(req.reference_frame)
            if frame is not None:
                pose = tf.relative(frame[0], pose)
                twist = tf.twist_in_frame(frame[0], frame[1], twist)
            resp.link_state.link_name = req.link_name
            pose_to_msg(pose, resp.link_state.pose)
            twist_to_msg(twist, resp.link_state.twist)
            resp.link_state.reference_frame = req.reference_frame
            return "got state"
        return self._run(do, resp, "GetLinkState")

    def _set_model_configuration(self, req):
        def do():
            m = self._model(req.model_name)
            if len(req.joint_names) != len(req.joint_positions):
                raise RequestError("%d joint_names but %d joint_positions"
                                   % (len(req.joint_names), len(req.joint_positions)))
            unknown = [j for j in req.joint_names if j not in m.joints]
            if unknown:
                raise RequestError("model [%s] has no joint %s (joints: %s)" % (
                    req.model_name, ", ".join(unknown), ", ".join(m.joints)))
            if not tf.is_finite(tuple(req.joint_positions)):
                raise RequestError("joint_positions has a NaN or infinite value: %s" % (req.joint_positions,))
            m.set_configuration(list(req.joint_names), [float(v) for v in req.joint_positions])
            return "set model configuration done"
        return self._run(do, gzs.SetModelConfigurationResponse(), "SetModelConfiguration")

    # ---- properties -------------------------------------------------------------------------------
    def _get_world_properties(self, req):
        resp = gzs.GetWorldPropertiesResponse()

        def do():
            resp.sim_time = self.world.time
            resp.model_names = list(self.world.models)
            resp.rendering_enabled = False
            return "GetWorldProperties: got properties"
        self._run(do, resp, "GetWorldProperties")
        resp.status_message = "GetWorldProperties: got properties" if resp.success else resp.status_message
        return resp

    def _get_model_properties(self, req):
        resp = gzs.GetModelPropertiesResponse()

        def do():
            m = self._model(req.model_name)
            info = description.parse_links(m.source_xml, m.name) if getattr(m, "source_xml", None) else {}
            resp.parent_model_name = ""
            resp.canonical_body_name = m.canonical_link.name if m.canonical_link is not None else ""
            resp.body_names = list(m.links)
            resp.geom_names = [g for lname in m.links if lname in info for g in info[lname].collision_names]
            resp.joint_names = [n for n, j in m.joints.items() if j.type != "fixed"]
            resp.child_model_names = []
            resp.is_static = bool(m.is_static)
            return "got properties"
        return self._run(do, resp, "GetModelProperties")

    def _get_joint_properties(self, req):
        resp = gzs.GetJointPropertiesResponse()

        def do():
            j = self._find_joint(req.joint_name)
            if j is None:
                raise RequestError("joint [%s] does not exist" % req.joint_name)
            resp.type = JOINT_TYPE.get(j.type, gzs.GetJointPropertiesResponse.FIXED)
            if j.type == "fixed":
                resp.damping, resp.position, resp.rate = [], [], []
            else:
                resp.damping = [float(j.damping or 0.0)]
                resp.position = [float(j.position)]
                resp.rate = [float(j.velocity)]
            return "got properties"
        return self._run(do, resp, "GetJointProperties")

    def _inertial_origin(self, link):
        origin = getattr(link, "inertial_origin", None)
        if origin is not None:
            return origin
        m = link.model
        info = description.parse_links(m.source_xml, m.name) if getattr(m, "source_xml", None) else {}
        return info[link.name].inertial_origin if link.name in info else tf.IDENTITY

    def _get_link_properties(self, req):
        resp = gzs.GetLinkPropertiesResponse()

        def do():
            link = self._find_link(req.link_name)
            if link is None:
                raise RequestError(NO_LINK % req.link_name)
            pose_to_msg(self._inertial_origin(link), resp.com)
            resp.gravity_mode = bool(link.gravity_enabled)
            resp.mass = float(link.mass)
            (resp.ixx, resp.ixy, resp.ixz, resp.iyy, resp.iyz, resp.izz) = [float(v) for v in link.inertia]
            return "got properties"
        return self._run(do, resp, "GetLinkProperties")

    def _set_link_properties(self, req):
        def do():
            link = self._find_link(req.link_name)
            if link is None:
                raise RequestError(NO_LINK % req.link_name)
            inertia = (req.ixx, req.ixy, req.ixz, req.iyy, req.iyz, req.izz)
            com = pose_from_msg(req.com, "com")
            if not tf.is_finite(inertia, req.mass):
                raise RequestError("mass or inertia has a NaN or infinite value")
            changed = abs(req.mass - link.mass) > 1e-12 or any(
                abs(a - b) > 1e-12 for a, b in zip(inertia, link.inertia))
            if changed:
                setter = getattr(link, "set_inertial", None)
                if setter is None:
                    raise RequestError("changing mass/inertia of a link is not supported by this simulator; "
                                       "only gravity_mode can be set (send the current mass and inertia)")
                if req.mass <= 0:
                    raise RequestError("mass must be positive, got %g" % req.mass)
                setter(req.mass, inertia, com)
            link.gravity_enabled = bool(req.gravity_mode)
            return "set link properties done"
        return self._run(do, gzs.SetLinkPropertiesResponse(), "SetLinkProperties")

    # ---- forces -----------------------------------------------------------------------------------
    def _start_and_duration(self, start_time, duration):
        """(start sim time, duration in s or None for 'until cleared'), Gazebo's semantics."""
        now = self.world.time
        start = start_time.to_sec()
        if start < now:
            start = now
        d = duration.to_sec()
        if d < 0:
            return start, None
        return start, max(d, self.world.time_step)

    def _apply_body_wrench(self, req):
        def do():
            link = self._find_link(req.body_name)
            if link is None:
                raise RequestError("body_name [%s] does not exist; use the scoped name model::link"
                                   % req.body_name)
            f = (req.wrench.force.x, req.wrench.force.y, req.wrench.force.z)
            tq = (req.wrench.torque.x, req.wrench.torque.y, req.wrench.torque.z)
            p = (req.reference_point.x, req.reference_point.y, req.reference_point.z)
            if not tf.is_finite(f, tq, p):
                raise RequestError("wrench or reference_point has a NaN or infinite value")
            if req.duration.to_sec() == 0.0:
                return "duration is 0: nothing applied"
            frame = self._frame(req.reference_frame)
            link_pose = link.pose
            if frame is not None:     # wrench and point given in that frame: rotate / move to world
                q = frame[0][1]
                f, tq = tf.quat_rotate(q, f), tf.quat_rotate(q, tq)
                p_world = tf.add(frame[0][0], tf.quat_rotate(q, p))
            else:                     # world axes, point relative to the body's origin
                p_world = tf.add(link_pose[0], p)
            # the core takes the point in the link frame (where the force acts on the link)
            p = tf.quat_rotate(tf.quat_conj(link_pose[1]), tf.sub(p_world, link_pose[0]))
            start, duration = self._start_and_duration(req.start_time, req.duration)
            self._wrench_jobs.append(_WrenchJob(link, f, tq, p, start, duration))
            self._activate_wrenches(self.world.time)
            return "wrench applied to [%s] from t=%.3f s %s" % (
                req.body_name, start, "until cleared" if duration is None else "for %.3f s" % duration)
        return self._run(do, gzs.ApplyBodyWrenchResponse(), "ApplyBodyWrench")

    def _activate_wrenches(self, t):
        keep = []
        for job in self._wrench_jobs:
            if job.start <= t + 1e-12:
                duration = job.duration
                if duration is not None:
                    duration = max(self.world.time_step, duration - (t - job.start))
                job.link.add_wrench(job.force, job.torque, reference_point=job.point, duration=duration)
            else:
                keep.append(job)
        self._wrench_jobs = keep

    def _apply_joint_effort(self, req):
        def do():
            joint = self._find_joint(req.joint_name)
            if joint is None:
                raise RequestError("joint [%s] does not exist" % req.joint_name)
            if not math.isfinite(req.effort):
                raise RequestError("effort is NaN or infinite")
            if req.duration.to_sec() == 0.0:
                return "duration is 0: nothing applied"
            start, duration = self._start_and_duration(req.start_time, req.duration)
            end = None if duration is None else start + duration
            self._effort_jobs.append(_EffortJob(joint, float(req.effort), start, end))
            return "effort %g on [%s] from t=%.3f s %s" % (
                req.effort, req.joint_name, start,
                "until cleared" if end is None else "for %.3f s" % duration)
        return self._run(do, gzs.ApplyJointEffortResponse(), "ApplyJointEffort")

    def _apply_efforts(self, t, dt):
        total = {}
        keep = []
        for job in self._effort_jobs:
            if job.end is not None and t >= job.end - 1e-12:
                continue
            keep.append(job)
            if t + 1e-12 >= job.start:
                total[job.joint] = total.get(job.joint, 0.0) + job.effort
        self._effort_jobs = keep
        for joint, effort in total.items():
            # Gazebo's SetForce adds up within a step: added to what a controller set this step
            joint.add_effort(effort)

    def _clear_body_wrenches(self, req):
        def do():
            link = self._find_link(req.body_name)
            if link is None:
                raise RequestError("body_name [%s] does not exist" % req.body_name)
            link.clear_wrenches()
            self._wrench_jobs = [j for j in self._wrench_jobs if j.link is not link]
        self._run(do, _Status(), "ClearBodyWrenches")
        return gzs.BodyRequestResponse()

    def _clear_joint_forces(self, req):
        def do():
            joint = self._find_joint(req.joint_name)
            if joint is None:
                raise RequestError("joint [%s] does not exist" % req.joint_name)
            self._effort_jobs = [j for j in self._effort_jobs if j.joint is not joint]
        self._run(do, _Status(), "ClearJointForces")
        return gzs.JointRequestResponse()

    # ---- physics control --------------------------------------------------------------------------
    def _pause(self, req):
        def do():   # between two steps: the last /clock then tells the exact paused time
            self.loop.set_paused(True)
            self._publish_clock()
        self.loop.call(do)
        return EmptyResponse()

    def _unpause(self, req):
        self.loop.set_paused(False)
        return EmptyResponse()

    def _after_reset(self, reseed):
        self._wrench_jobs, self._effort_jobs = [], []
        self.loop.reset_pacing()
        self._next_state_t = 0.0
        self._next_marker_t = 0.0
        self.plugins.reset(reseed)
        self._publish_clock(force=True)
        self._publish_states()
        self._publish_markers(force=True)

    def _reset_simulation(self, req):
        def do():
            self.world.reset()
            self._after_reset(reseed=True)
            return "reset"
        self._run(do, _Status(), "ResetSimulation")
        return EmptyResponse()

    def _reset_world(self, req):
        def do():
            self.world.reset_world()
            self._after_reset(reseed=False)
            return "reset"
        self._run(do, _Status(), "ResetWorld")
        return EmptyResponse()

    def _get_physics_properties(self, req):
        resp = gzs.GetPhysicsPropertiesResponse()

        def do():
            w = self.world
            resp.time_step = w.time_step
            resp.pause = self.loop.paused
            rtf = self.loop.real_time_factor
            resp.max_update_rate = rtf / w.time_step if rtf > 0 else 0.0
            resp.gravity = Vector3(*w.gravity)
            pp = w.physics_params
            cfg = resp.ode_config
            for key, field in ODE_FIELDS:
                if key in pp:
                    setattr(cfg, field, type(getattr(cfg, field))(pp[key]))
            cfg.auto_disable_bodies = False
            return "GetPhysicsProperties: got properties"
        self._run(do, resp, "GetPhysicsProperties")
        return resp

    def _set_physics_properties(self, req):
        def do():
            if not (req.time_step > 0 and math.isfinite(req.time_step)):
                raise RequestError("time_step must be a positive number of seconds, got %r" % req.time_step)
            if not (req.max_update_rate >= 0 and math.isfinite(req.max_update_rate)):
                raise RequestError("max_update_rate must be >= 0 (0 = as fast as possible), got %r"
                                   % req.max_update_rate)
            g = (req.gravity.x, req.gravity.y, req.gravity.z)
            if not tf.is_finite(g):
                raise RequestError("gravity has a NaN or infinite value")
            cfg = req.ode_config
            ode = {}
            if any(getattr(cfg, field) for _, field in ODE_FIELDS):  # all zero = not given: keep
                for key, field in ODE_FIELDS:
                    ode[key] = getattr(cfg, field)
                if ode["iters"] <= 0:
                    raise RequestError("ode_config.sor_pgs_iters must be positive")
            self.world.time_step = req.time_step
            self.world.gravity = g
            if ode:
                self.world.set_physics_params(**ode)
            self.loop.set_real_time_factor(req.max_update_rate * req.time_step)
            return "physics properties set"
        return self._run(do, gzs.SetPhysicsPropertiesResponse(), "SetPhysicsProperties")

    def _step(self, req):
        resp = StepSimulationResponse()

        def do():
            if not self.loop.paused:
                raise RequestError("physics is running: call /gazebo/pause_physics first (step advances "
                                   "a paused simulation by exactly N steps)")
            if req.steps > 0:
                self.world.step(int(req.steps))
                self._publish_clock()   # the throttled clock may have skipped the last step
            resp.iterations = self.world.iterations
            resp.sim_time = self.world.time
            return "advanced %d steps to t=%.6f s" % (req.steps, self.world.time)
        return self._run(do, resp, "Step", timeout=None)   # N steps take as long as they take


def ensure_use_sim_time():
    """Set /use_sim_time to true when nobody has set it, as gazebo_ros does (call before
    rospy.init_node so that this process's rospy also follows /clock)."""
    import rosgraph
    try:
        master = rosgraph.Master("/gazebo_setup")
        if not master.hasParam("/use_sim_time"):
            master.setParam("/use_sim_time", True)
    except Exception as exc:  # noqa: B902 - no master yet: init_node will report it
        sys.stderr.write("gazebo: could not check /use_sim_time: %s\n" % exc)


class _RospyHandler(logging.Handler):
    """Python logging of the pure libraries (modrob_sim.physics ...) to rosout."""

    def emit(self, record):
        text = self.format(record)
        if record.levelno >= logging.ERROR:
            rospy.logerr(text)
        elif record.levelno >= logging.WARNING:
            rospy.logwarn(text)
        elif record.levelno >= logging.INFO:
            rospy.loginfo(text)
        else:
            rospy.logdebug(text)


def forward_python_logging(name):
    logger = logging.getLogger(name)
    if not any(isinstance(h, _RospyHandler) for h in logger.handlers):
        logger.addHandler(_RospyHandler())
        logger.setLevel(logging.INFO)
        logger.propagate = False


def take_over_sim_time():
    """In this process rospy would follow /clock by subscribing to it: the node would send every
    clock message to itself. Drop that subscription; the loop sets rospy's time directly before
    each step instead (so rospy.Time.now() in plugins is the step's time). True when sim time is
    in use here."""
    from rospy.impl import simtime
    sub = getattr(simtime, "_clock_sub", None)
    if sub is None or rospy.rostime.is_wallclock():
        return False
    sub.unregister()
    simtime._clock_sub = None
    return True
