"""A probe plugin for sim_plugins.test (imported by /gazebo through ~plugin_modules): reports on a
latched topic /probe/<model> how it was created and called (robot namespace, update count, time
of the last update, resets, shutdown), so the test can check the plugin contract."""
from std_msgs.msg import String

from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin


class Probe(ModelPlugin):
    def load(self, model, spec, ctx):
        self.ns = spec.robot_namespace
        self.ctx_ns = ctx.robot_namespace
        self.updates = 0
        self.last_t = -1.0
        self.resets = 0
        self.first_random = self.rng.random()
        self.pub = ctx.advertise("/probe/%s" % model.name, String, queue_size=1, latch=True)
        self.report("created")

    def report(self, state):
        text = "state=%s ns=%s ctx_ns=%s updates=%d last_t=%.6f resets=%d first_random=%.9f" % (
            state, self.ns, self.ctx_ns, self.updates, self.last_t, self.resets, self.first_random)
        self.pub.publish_later(lambda: String(data=text))   # built in the node's publishing thread

    def before_step(self, t, dt):
        self.updates += 1
        self.last_t = t

    def after_step(self, t, dt):
        if self.updates % 50 == 0:
            self.report("running")

    def reset(self):
        self.resets += 1
        self.updates = 0
        self.first_random = self.rng.random()   # re-seeded by reset_simulation: the same draw
        self.report("reset")

    def shutdown(self):
        self.report("shutdown")


register_plugin("libsim_probe.so", Probe)
