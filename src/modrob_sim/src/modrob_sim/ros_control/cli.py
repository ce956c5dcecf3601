"""The command-line tools of ros_control's controller_manager package, with the same arguments:
``spawner``, ``unspawner`` and ``controller_manager`` (the scripts in modrob_sim/scripts call the
``*_main`` functions here).

The spawner waits for the controller manager's services AND, with use_sim_time, for /clock to
tick (the usual reason why Gazebo spawners time out: physics paused or not started yet), loads
its controllers (names, or YAML files that are first put on the parameter server), starts them
(unless --stopped) and on shutdown (SIGINT, roslaunch stopping it) stops and unloads them.
"""
import argparse
import os
import socket
import sys
import time

import rosgraph
import rosparam
import rospy
import yaml
from controller_manager_msgs.srv import (ListControllers, ListControllerTypes, LoadController,
                                         ReloadControllerLibraries, SwitchController, SwitchControllerRequest,
                                         UnloadController)
from std_msgs.msg import Bool

from modrob_sim.waits import stop_following_clock

STRICT = SwitchControllerRequest.STRICT
BEST_EFFORT = SwitchControllerRequest.BEST_EFFORT


def _service_names(namespace):
    prefix = namespace.rstrip("/") + "/" if namespace else ""
    return {k: prefix + "controller_manager/" + k for k in
            ("load_controller", "unload_controller", "switch_controller", "list_controllers",
             "list_controller_types", "reload_controller_libraries")}


class ManagerClient(object):
    TYPES = {"load_controller": LoadController, "unload_controller": UnloadController,
             "switch_controller": SwitchController, "list_controllers": ListControllers,
             "list_controller_types": ListControllerTypes,
             "reload_controller_libraries": ReloadControllerLibraries}

    def __init__(self, namespace=""):
        self.names = _service_names(namespace)
        self.proxies = {k: rospy.ServiceProxy(v, self.TYPES[k]) for k, v in self.names.items()}

    def wait(self, timeout, which=("load_controller", "switch_controller", "unload_controller"),
             who="Controller Spawner"):
        for k in which:
            name = rospy.resolve_name(self.names[k])
            rospy.loginfo("%s: Waiting for service %s" % (who, name))
            rospy.wait_for_service(name, timeout=timeout)

    def __getattr__(self, name):
        proxies = self.__dict__.get("proxies", {})
        if name in proxies:
            return proxies[name]
        raise AttributeError(name)


def wait_for_clock(timeout):
    """With use_sim_time, wait until /clock has ticked (wall-clock timeout; None = forever)."""
    if not rospy.get_param("/use_sim_time", False):
        return True
    start, warned = time.monotonic(), 0.0
    while not rospy.is_shutdown():
        if rospy.get_rostime().to_sec() > 0.0:
            return True
        waited = time.monotonic() - start
        if timeout is not None and waited > timeout:
            return False
        if waited - warned > 5.0:
            warned = waited
            rospy.loginfo("Controller Spawner: use_sim_time is set and /clock has not ticked yet after "
                          "%.0f s "
                          "(is the simulation paused? call /gazebo/unpause_physics)" % waited)
        time.sleep(0.05)
    return False


def expand_controllers(names):
    """Controller names, or YAML files whose top-level keys are controllers (the file is loaded
    onto the parameter server in the node's namespace first, as ros_control's spawner does)."""
    out = []
    for name in names:
        if os.path.isfile(name):
            try:
                with open(name) as f:
                    content = yaml.safe_load(f)
            except (OSError, yaml.YAMLError) as exc:
                raise SystemExit("spawner: cannot read controller file %s: %s" % (name, exc))
            if not isinstance(content, dict):
                raise SystemExit("spawner: %s must map controller names to their parameters" % name)
            for params, ns in rosparam.load_file(name, default_namespace=rospy.get_namespace()):
                rosparam.upload_params(ns, params)
            out.extend(content.keys())
        else:
            out.append(name)
    return out


def spawner_parser():
    p = argparse.ArgumentParser(prog="spawner", description="Controller spawner: loads and starts "
                                                            "controllers, "
                                "stops and unloads them when it is shut down.")
    p.add_argument("--stopped", action="store_true", help="loads controllers, but does not start them")
    p.add_argument("--wait-for", metavar="topic",
                   help='does not load or start controllers until it hears "True" on a topic (Bool)')
    p.add_argument("--namespace", metavar="ns", help="namespace of the controller_manager services")
    p.add_argument("--timeout", metavar="T", type=float, default=30,
                   help="how long to wait for controller_manager services when starting up [s] (default: 30)")
    p.add_argument("--no-timeout", action="store_true", help="wait for the controller_manager services "
                                                             "forever")
    p.add_argument("--shutdown-timeout", metavar="T", type=float, default=30,
                   help="how long to wait for controller_manager services when shutting down [s] "
                        "(default: 30)")
    p.add_argument("controllers", metavar="controller", nargs="+", help="controllers (or YAML files) to load")
    return p


def spawner_main(argv=None):
    args = spawner_parser().parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    rospy.init_node("spawner", anonymous=True)
    timeout = None if args.no_timeout else args.timeout
    client = ManagerClient(args.namespace or "")
    try:
        client.wait(timeout)
    except rospy.ROSException:
        rospy.logerr("Controller Spawner couldn't find the expected controller_manager ROS interface "
                     "(%s) within "
                     "%g s: is the simulator running and does the robot's URDF have the gazebo_ros_control "
                     "plugin with this robotNamespace?"
                     % (rospy.resolve_name(client.names["load_controller"]), timeout))
        return 1
    if not wait_for_clock(timeout):
        if rospy.is_shutdown():
            return 0
        rospy.logerr("Controller Spawner: /clock did not tick within %g s although use_sim_time is set: "
                     "is the "
                     "simulation paused (/gazebo/unpause_physics)?" % timeout)
        return 1
    if args.wait_for and not _wait_for_true(args.wait_for, timeout):
        return 0
    controllers = expand_controllers(args.controllers)
    loaded = []

    rospy.on_shutdown(lambda: take_down(client, loaded, args.shutdown_timeout))
    try:
        for name in controllers:
            rospy.loginfo("Loading controller: %s" % name)
            if client.load_controller(name).ok:
                loaded.append(name)
            else:
                rospy.logerr("Failed to load %s (the simulator's log says why)" % name)
        rospy.loginfo("Controller Spawner: Loaded controllers: %s" % ", ".join(loaded))
        if loaded and not args.stopped and not rospy.is_shutdown():
            if client.switch_controller(loaded, [], STRICT, False, 0.0).ok:
                rospy.loginfo("Started controllers: %s" % ", ".join(loaded))
            else:
                rospy.logerr("Failed to start controllers: %s" % ", ".join(loaded))
    except (rospy.ServiceException, rospy.ROSException) as exc:
        load = rospy.resolve_name(client.names["load_controller"])
        if rospy.is_shutdown() or not _service_registered(load):
            # stopped (Ctrl-C, the launch ending) while it was still loading: nothing went wrong
            rospy.loginfo("Controller Spawner: stopped while loading controllers (the simulator is gone)")
            return 0
        rospy.logerr("Controller Spawner: the controller_manager stopped answering (%s); the simulator's log "
                     "says why" % exc)
        return 1
    # from here on it only waits to take the controllers down (wall-clock timeouts): /clock would
    # cost it CPU at every message, beside the simulator
    stop_following_clock()
    rospy.spin()
    return 0


# a request to a simulator that is shutting down itself can be accepted and never answered (its
# listening socket still open, its service threads gone): each one is bounded so that the spawner
# ends before roslaunch escalates to SIGTERM (15 s after Ctrl-C)
SHUTDOWN_REQUEST_TIMEOUT = 4.0  # wall seconds
GONE_WAIT = 3.0  # wall seconds for a simulator that did not answer to leave the master


def take_down(client, loaded, shutdown_timeout, registered=None):
    """The spawner's shutdown: stop and unload the controllers it ``loaded`` through ``client``
    (a ManagerClient), quietly when the simulator stopped first (the usual end of a launch:
    roslaunch stops every node at once). ``registered(name)`` tells whether the master still
    lists a service (the master by default)."""
    registered = registered or _service_registered
    rospy.loginfo("Shutting down spawner. Stopping and unloading controllers...")
    t0 = time.monotonic()
    names = [rospy.resolve_name(client.names[k]) for k in ("switch_controller", "unload_controller")]
    socket.setdefaulttimeout(min(shutdown_timeout, SHUTDOWN_REQUEST_TIMEOUT))
    try:
        for name in names:
            if not registered(name):
                # the simulator went down with us: waiting --shutdown-timeout for it would only keep
                # roslaunch (and this process) around
                rospy.loginfo("Controller Spawner: %s is no longer offered (the simulator has "
                              "stopped): nothing to stop or unload" % name)
                return
            rospy.wait_for_service(name, timeout=shutdown_timeout)
        # BEST_EFFORT: a controller the simulator already stopped (its model deleted, or another
        # spawner) is not an error at tear-down
        client.switch_controller([], loaded, BEST_EFFORT, False, 0.0)
        for name in reversed(loaded):
            if client.unload_controller(name).ok:
                rospy.loginfo("Unloaded %s" % name)
            else:
                rospy.logwarn("Could not unload %s (the simulator's log says why)" % name)
    except (rospy.ServiceException, rospy.ROSException) as exc:
        end = time.monotonic() + GONE_WAIT
        while all(registered(n) for n in names) and time.monotonic() < end:
            time.sleep(0.05)
        if not all(registered(n) for n in names):
            # the simulator stopped between the look above and the request, or while it was asked:
            # its controllers went with it
            rospy.loginfo("Controller Spawner: the controller_manager went away with the simulator, "
                          "and its controllers with it")
            return
        rospy.logwarn("Controller Spawner couldn't reach controller_manager to take down "
                      "controllers (%s) after %.1f s" % (exc, time.monotonic() - t0))
    finally:
        socket.setdefaulttimeout(None)


def _service_registered(name):
    """Whether the master still lists the service ``name`` (False when the master is gone too)."""
    try:
        rosgraph.Master(rospy.get_name()).lookupService(name)
        return True
    except (rosgraph.MasterException, OSError):
        return False


def _wait_for_true(topic, timeout):
    heard = []
    rospy.Subscriber(topic, Bool, lambda m: heard.append(m.data))
    start, warned = time.monotonic(), False
    while not (heard and heard[-1]):
        if rospy.is_shutdown():
            return False
        if not heard and not warned and timeout is not None and time.monotonic() - start > timeout:
            warned = True
            rospy.logwarn('Controller Spawner hasn\'t heard anything from its "wait for" topic (%s)' % topic)
        time.sleep(0.01)
    return True


def unspawner_main(argv=None):
    """ros_control's unspawner: stops the controllers while it runs, restarts them when killed."""
    p = argparse.ArgumentParser(prog="unspawner", description="Stops controllers while running, "
                                                              "restarts them "
                                "when shut down.")
    p.add_argument("--namespace", metavar="ns", help="namespace of the controller_manager services")
    p.add_argument("--timeout", metavar="T", type=float, default=30)
    p.add_argument("--shutdown-timeout", metavar="T", type=float, default=30)
    p.add_argument("controllers", metavar="controller", nargs="+")
    args = p.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    rospy.init_node("unspawner", anonymous=True)
    client = ManagerClient(args.namespace or "")
    try:
        client.wait(args.timeout, ("switch_controller",), who="unspawner")
    except rospy.ROSException:
        rospy.logerr("unspawner: no controller_manager at %s"
                     % rospy.resolve_name(client.names["switch_controller"]))
        return 1
    if not client.switch_controller([], args.controllers, STRICT, False, 0.0).ok:
        rospy.logerr("unspawner: could not stop %s" % ", ".join(args.controllers))
        return 1
    rospy.loginfo("Stopped controllers: %s" % ", ".join(args.controllers))

    def restart():
        try:
            rospy.wait_for_service(rospy.resolve_name(client.names["switch_controller"]),
                                   args.shutdown_timeout)
            client.switch_controller(args.controllers, [], STRICT, False, 0.0)
        except (rospy.ServiceException, rospy.ROSException) as exc:
            rospy.logwarn("unspawner: could not restart the controllers: %s" % exc)
    rospy.on_shutdown(restart)
    rospy.spin()
    return 0


COMMANDS = ("load", "unload", "start", "stop", "spawn", "kill", "list", "list-types", "reload-libraries")


def controller_manager_main(argv=None):
    """``controller_manager <command> [controllers]`` as ros_control's script."""
    p = argparse.ArgumentParser(prog="controller_manager")
    p.add_argument("--namespace", metavar="ns", default="", help="namespace of the controller_manager "
                                                                 "services")
    p.add_argument("--timeout", metavar="T", type=float, default=30)
    p.add_argument("command", choices=COMMANDS)
    p.add_argument("controllers", nargs="*")
    p.add_argument("--restore", action="store_true", help="reload-libraries: reload the controllers "
                                                          "afterwards")
    args = p.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    rospy.init_node("controller_manager_cli", anonymous=True, disable_signals=True)
    client = ManagerClient(args.namespace)
    try:
        client.wait(args.timeout, ("list_controllers",), who="controller_manager")
    except rospy.ROSException:
        print("no controller_manager at %s" % rospy.resolve_name(client.names["list_controllers"]),
              file=sys.stderr)
        return 1
    c = args.controllers
    ok = True
    if args.command == "list":
        for s in client.list_controllers().controller:
            res = "; ".join("%s: %s" % (r.hardware_interface,
                                        ", ".join(r.resources)) for r in s.claimed_resources)
            print("%s - %s ( %s )%s" % (s.name, s.type, s.state, ("  [" + res + "]") if res else ""))
    elif args.command == "list-types":
        for t in client.list_controller_types().types:
            print(t)
    elif args.command == "reload-libraries":
        names = [s.name for s in client.list_controllers().controller]
        ok = client.reload_controller_libraries(True).ok
        if ok and args.restore:
            for n in names:
                ok = client.load_controller(n).ok and ok
    else:
        for name in c:
            if args.command in ("load", "spawn"):
                ok = client.load_controller(name).ok and ok
            if args.command in ("stop", "kill"):
                ok = client.switch_controller([], [name], STRICT, False, 0.0).ok and ok
            if args.command in ("start", "spawn"):
                ok = client.switch_controller([name], [], STRICT, False, 0.0).ok and ok
            if args.command in ("unload", "kill"):
                ok = client.unload_controller(name).ok and ok
            print("%s %s: %s" % (args.command, name, "ok" if ok else "FAILED (see the simulator's log)"))
    return 0 if ok else 1
