"""pause/unpause_physics, reset_simulation/reset_world, get/set_physics_properties, step."""
import math

import rospy
from gazebo_msgs import srv as gzs
from geometry_msgs.msg import Vector3
from std_srvs.srv import Empty, EmptyResponse

from modrob_msgs.srv import StepSimulation, StepSimulationResponse
from modrob_sim.errors import RequestError
from modrob_sim.gazebo_ros.services.base import ServiceGroup, Status
from modrob_sim.physics import limits

#: physics_params keys of the core <-> fields of gazebo_msgs/ODEPhysics
ODE_FIELDS = (("iters", "sor_pgs_iters"), ("sor", "sor_pgs_w"), ("cfm", "cfm"), ("erp", "erp"),
              ("contact_max_correcting_vel", "contact_max_correcting_vel"),
              ("contact_surface_layer", "contact_surface_layer"), ("max_contacts", "max_contacts"))


def _not_applied(cfg):
    """The gazebo_msgs/ODEPhysics fields that ask for something ODE 0.16's quickStep cannot do,
    said in words (empty when none does). Gazebo's own defaults (both 0) ask for nothing."""
    out = []
    tol = cfg.sor_pgs_rms_error_tol
    if tol != 0.0:
        out.append("sor_pgs_rms_error_tol %g (ODE 0.16's quickStep has no early exit: every step runs "
                   "all sor_pgs_iters iterations, as Gazebo does with its default 0; lower "
                   "sor_pgs_iters for fewer)" % tol)
    if cfg.sor_pgs_precon_iters != 0:
        out.append("sor_pgs_precon_iters %d (ODE 0.16's quickStep has no preconditioning iterations)"
                   % cfg.sor_pgs_precon_iters)
    return "; ".join(out)


#: steps of a `step` request between two checks for shut-down
STEP_CHUNK = 100


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
            self.sim.outputs.on_pause()
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
            # everything is checked before anything is applied: a refusal changes nothing
            try:
                dt = limits.check_time_step(req.time_step, "time_step")
                g = limits.check_gravity((req.gravity.x, req.gravity.y, req.gravity.z), "gravity")
            except ValueError as exc:
                raise RequestError("%s; nothing applied" % exc)
            if not (req.max_update_rate >= 0 and math.isfinite(req.max_update_rate)
                    and req.max_update_rate * dt <= 1e6):
                raise RequestError("max_update_rate must be >= 0 (0 = as fast as possible) and at most "
                                   "1e6 times real time, got %r; nothing applied" % req.max_update_rate)
            cfg = req.ode_config
            ode = {}
            if any(getattr(cfg, field) for _, field in ODE_FIELDS):  # all zero = not given: keep
                for key, field in ODE_FIELDS:
                    ode[key] = getattr(cfg, field)
                if ode["iters"] <= 0:
                    raise RequestError("ode_config.sor_pgs_iters must be positive; nothing applied")
            if ode:
                try:   # validates every parameter before it changes any
                    self.world.set_physics_params(**ode)
                except ValueError as exc:
                    raise RequestError("ode_config: %s; nothing applied" % exc)
            self.world.time_step = dt
            self.world.gravity = g
            self.loop.set_real_time_factor(req.max_update_rate * dt)
            ignored = _not_applied(cfg)
            if ignored:
                rospy.logwarn("set_physics_properties: not applied: %s", ignored)
                return "physics properties set; not applied: %s" % ignored
            return "physics properties set"
        return self.run(do, gzs.SetPhysicsPropertiesResponse(), "SetPhysicsProperties")

    def step(self, req):
        resp = StepSimulationResponse()

        def do():
            if not self.loop.paused:
                raise RequestError("physics is running: call /gazebo/pause_physics first (step advances "
                                   "a paused simulation by exactly N steps)")
            if req.steps > 0:
                # in chunks, so that shut-down stops a long request at once (the node exited while
                # the loop thread was still inside ODE: SIGABRT/SIGSEGV in its tear-down)
                left = int(req.steps)
                while left > 0:
                    if self.loop.stopping:
                        raise RequestError("the node is shutting down: stopped at t=%.6f s with %d of %d "
                                           "steps left" % (self.world.time, left, req.steps))
                    n = min(left, STEP_CHUNK)
                    self.world.step(n)
                    self.sim.outputs.after_pass()       # /clock as it goes, as the loop's passes
                    left -= n
                self.sim.outputs.on_pause()     # still paused: /clock and the markers as it stands
            resp.iterations = self.world.iterations
            resp.sim_time = self.world.time
            return "advanced %d steps to t=%.6f s" % (req.steps, self.world.time)
        return self.run(do, resp, "Step", timeout=None)   # N steps take as long as they take
