"""A probe plugin for sim_plugins.test (imported by /gazebo through ~plugin_modules): reports on a
latched topic /probe/<model> how it was created and called (robot namespace, update count, time
of the last update, resets, shutdown), so the test can check the plugin contract."""
import rospy
from std_msgs.msg import String

from modrob_sim.gazebo_ros.plugins import register_plugin


class Probe(object):
    def __init__(self, model, spec, ctx):
        self.ns = spec.robot_namespace
        self.ctx_ns = ctx.robot_namespace
        self.updates = 0
        self.last_t = -1.0
        self.resets = 0
        self.pub = rospy.Publisher("/probe/%s" % model.name, String, queue_size=1, latch=True)
        self.report("created")

    def report(self, state):
        self.pub.publish(String(data="state=%s ns=%s ctx_ns=%s updates=%d last_t=%.6f resets=%d" % (
            state, self.ns, self.ctx_ns, self.updates, self.last_t, self.resets)))

    def update(self, t, dt):
        self.updates += 1
        self.last_t = t

    def after_step(self, t, dt):
        if self.updates % 50 == 0:
            self.report("running")

    def reset(self):
        self.resets += 1
        self.updates = 0
        self.report("reset")

    def shutdown(self):
        self.report("shutdown")


register_plugin("libsim_probe.so", Probe)
