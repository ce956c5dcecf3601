"""What every service group shares: the simulation it serves and the one way a request reaches
the World (a job in the loop thread, errors turned into success: false + status_message)."""
import collections

import rospy

from modrob_sim.errors import ModrobError

#: the parts of the node that services use (built by the node, see server.py)
Sim = collections.namedtuple("Sim", "world loop lookup forces outputs plugins")


class Status(object):
    """success / status_message holder for services whose response has neither (std_srvs/Empty)."""
    success = False
    status_message = ""


class ServiceGroup(object):
    def __init__(self, sim):
        self.sim = sim
        self.world = sim.world
        self.loop = sim.loop
        self.lookup = sim.lookup

    def advertise(self):
        """Create the group's rospy services (and subscribers); returns them."""
        raise NotImplementedError

    def run(self, fn, response, name, timeout=120.0):
        """Run fn() in the loop; fill response.success / status_message. fn returns a message."""
        try:
            text = self.loop.call(fn, timeout=timeout)
            response.success = True
            response.status_message = "%s: %s" % (name, text)
        except ModrobError as exc:
            response.success = False
            response.status_message = "%s: %s" % (name, exc)
            rospy.logwarn(response.status_message)
        return response

    def post(self, fn, what):
        """Run fn() in the loop for a topic callback: errors are logged, nobody waits for them."""
        def job():
            try:
                fn()
            except ModrobError as exc:
                rospy.logwarn("%s: %s" % (what, exc))
        try:
            self.loop.call(job)
        except ModrobError as exc:
            rospy.logwarn("%s: %s" % (what, exc))

    @staticmethod
    def unsupported(resp, name, what, why):
        resp.success = False
        resp.status_message = "%s: %s: not supported by this simulator: %s" % (name, what, why)
        rospy.logwarn(resp.status_message)
        return resp
