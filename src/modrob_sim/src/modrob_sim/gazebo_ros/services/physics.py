"""pause/unpause_physics, reset_simulation/reset_world, get/set_physics_properties, step."""
import math

import rospy
from gazebo_msgs import srv as gzs
from geometry_msgs.msg import Vector3
from std_srvs.srv import Empty, EmptyResponse

from modrob_msgs.srv import StepSimulation, StepSimulationResponse
from modrob_sim.errors import RequestError
from modrob_sim.gazebo_ros import transforms as tf
from modrob_sim.gazebo_ros.services.base import ServiceGroup, Status

#: physics_params keys of the core <-> fields of gazebo_msgs/ODEPhysics
ODE_FIELDS = (("iters", "sor_pgs_iters"), ("sor", "sor_pgs_w"), ("cfm", "cfm"), ("erp", "erp"),
              ("contact_max_correcting_vel", "contact_max_correcting_vel"),
              ("contact_surface_layer", "contact_surface_layer"), ("max_contacts", "max_contacts"))


class PhysicsServices(ServiceGroup):
    def advertise(self):
        S = rospy.Service
        return [
            S("~pause_physics", Empty, self.pause),
            S("~unpause_physics", Empty, self.unpause),
            S("~reset_simulation", Empty, self.reset_simulation),
            S("~reset_world", Empty, self.reset_world),
            S("~get_physics_properties", gzs.GetPhysicsProperties, self.get_physics_properties),
            S("~set_physics_properties", gzs.SetPhysicsProperties, self.set_physics_properties),
            S("~step", StepSimulation, self.step),
        ]

    def pause(self, req):
        def do():   # between two steps: the last /clock then tells the exact paused time
            self.loop.set_paused(True)
            self.sim.outputs.publish_clock()
        self.loop.call(do)
        return EmptyResponse()

    def unpause(self, req):
        self.loop.set_paused(False)
        return EmptyResponse()

    def _after_reset(self, reseed):
        self.sim.forces.reset()
        self.loop.reset_pacing()
        self.sim.plugins.reset(reseed)
        self.sim.outputs.after_reset()

    def reset_simulation(self, req):
        def do():
            self.world.reset()
            self._after_reset(reseed=True)
            return "reset"
        self.run(do, Status(), "ResetSimulation")
        return EmptyResponse()

    def reset_world(self, req):
        def do():
            self.world.reset_world()
            self._after_reset(reseed=False)
            return "reset"
        self.run(do, Status(), "ResetWorld")
        return EmptyResponse()

    def get_physics_properties(self, req):
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
        self.run(do, resp, "GetPhysicsProperties")
        return resp

    def set_physics_properties(self, req):
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
        return self.run(do, gzs.SetPhysicsPropertiesResponse(), "SetPhysicsProperties")

    def step(self, req):
        resp = StepSimulationResponse()

        def do():
            if not self.loop.paused:
                raise RequestError("physics is running: call /gazebo/pause_physics first (step advances "
                                   "a paused simulation by exactly N steps)")
            if req.steps > 0:
                self.world.step(int(req.steps))
                self.sim.outputs.publish_clock()   # the throttled clock may have skipped the last step
            resp.iterations = self.world.iterations
            resp.sim_time = self.world.time
            return "advanced %d steps to t=%.6f s" % (req.steps, self.world.time)
        return self.run(do, resp, "Step", timeout=None)   # N steps take as long as they take
