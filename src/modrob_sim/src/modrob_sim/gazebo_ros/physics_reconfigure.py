"""``/gazebo/set_parameters``: the physics through dynamic_reconfigure, as gazebo_ros offers it
(its Physics.cfg: rqt_reconfigure shows the world's physics under /gazebo).

Like gazebo_ros, the server starts with the world's current physics (read through
get_physics_properties) and applies a change through set_physics_properties, so a value is
checked by the same rules as the service and a refused one changes nothing (the server then
reports the values in force). Started once the node's loop runs; not offered when
``~enable_ros_network`` is false.
"""
import rospy
from dynamic_reconfigure.server import Server
from gazebo_msgs import srv as gzs

from modrob_sim.reconfigure_config import ConfigType, Param, shutdown_server

#: the highest max_update_rate the server takes, as gazebo_ros's Physics.cfg bounds it (steps per
#: wall second; set_physics_properties itself takes more)
MAX_UPDATE_RATE = 1000.0

#: gazebo_ros's Physics.cfg: name, type, default, min, max, text
PARAMS = (
    Param("time_step", "double", 0.001, 0.0, 10.0, "Simulation world time step size in seconds."),
    Param("max_update_rate", "double", 60.0, 0.0, MAX_UPDATE_RATE,
          "Steps per wall second at most: real_time_factor / time_step; 0 = as fast as possible."),
    Param("gravity_x", "double", 0.0, -100.0, 100.0, "Simulated gravity in the x direction."),
    Param("gravity_y", "double", 0.0, -100.0, 100.0, "Simulated gravity in the y direction."),
    Param("gravity_z", "double", -9.8, -100.0, 100.0, "Simulated gravity in the z direction."),
    Param("auto_disable_bodies", "bool", False, False, True,
          "Auto disable of bodies at rest (not applied here)."),
    Param("sor_pgs_precon_iters", "int", 0, 0, 10000, "Preconditioning iterations of quickstep."),
    Param("sor_pgs_iters", "int", 20, 0, 10000, "Iterations of the SOR PGS LCP solver (quickstep)."),
    Param("sor_pgs_w", "double", 1.3, 0.0, 5.0, "Relaxation parameter of SOR PGS."),
    Param("sor_pgs_rms_error_tol", "double", -1.0, -1.0, 10000.0, "RMS error tolerance of quickstep."),
    Param("cfm", "double", 0.0, 0.0, 10.0, "Constraint force mixing."),
    Param("erp", "double", 0.2, 0.0, 10.0, "Error reduction parameter."),
    Param("contact_surface_layer", "double", 0.001, 0.0, 10.0,
          "Penetration allowed before contacts push back."),
    Param("contact_max_correcting_vel", "double", 100.0, 0.0, 1e7, "Maximum contact correction velocity."),
    Param("max_contacts", "int", 100, 0, 10000000, "Maximum number of contacts between two bodies."),
)

_ODE = ("auto_disable_bodies", "sor_pgs_precon_iters", "sor_pgs_iters", "sor_pgs_w", "sor_pgs_rms_error_tol",
        "cfm", "erp", "contact_surface_layer", "contact_max_correcting_vel", "max_contacts")


def config_from(props):
    """Config values from a GetPhysicsProperties response."""
    cfg = {"time_step": props.time_step, "max_update_rate": props.max_update_rate,
           "gravity_x": props.gravity.x, "gravity_y": props.gravity.y, "gravity_z": props.gravity.z}
    for name in _ODE:
        cfg[name] = getattr(props.ode_config, name)
    return cfg


def request_from(config):
    """A SetPhysicsProperties request from config values."""
    req = gzs.SetPhysicsPropertiesRequest()
    req.time_step = config["time_step"]
    req.max_update_rate = config["max_update_rate"]
    req.gravity.x, req.gravity.y = config["gravity_x"], config["gravity_y"]
    req.gravity.z = config["gravity_z"]
    for name in _ODE:
        field = getattr(req.ode_config, name)
        setattr(req.ode_config, name, type(field)(config[name]))
    return req


class PhysicsReconfigure(object):
    """``physics`` has get_physics_properties(req) and set_physics_properties(req) (services.physics)."""

    def __init__(self, physics, namespace):
        self.physics = physics
        self._initialized = False
        self.server = Server(ConfigType(PARAMS), self._callback, namespace=namespace)

    def _callback(self, config, level):
        current = config_from(self.physics.get_physics_properties(gzs.GetPhysicsPropertiesRequest()))
        if not self._initialized:   # as gazebo_ros: the first call only reads the world's physics
            self._initialized = True
            config.update(current)
            return config
        if current["max_update_rate"] > MAX_UPDATE_RATE and config["max_update_rate"] == MAX_UPDATE_RATE:
            # the world runs faster than the server's bound (a world file's real_time_update_rate,
            # set_physics_properties): the server clamped it on a change of something else; keep it
            config["max_update_rate"] = current["max_update_rate"]
        if all(float(config[k]) == float(current[k]) for k in current):     # all numbers or bools
            return config
        resp = self.physics.set_physics_properties(request_from(config))
        if not resp.success:
            rospy.logwarn("/gazebo/set_parameters: %s" % resp.status_message)
            config.update(config_from(self.physics.get_physics_properties(gzs.GetPhysicsPropertiesRequest())))
        else:
            rospy.loginfo("physics dynamic reconfigure: %s" % resp.status_message)
        return config

    def shutdown(self):
        shutdown_server(self.server)
