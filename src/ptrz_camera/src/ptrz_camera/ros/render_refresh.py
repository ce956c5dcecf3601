"""render_refresh: keeps the off-screen renderer's cameras following moving frames.

modrob_viz's camera_renderer hands RViz each camera as a latched 1x1 placeholder image on
``/camera_renderer/<id>/image``, and RViz's camera display re-reads the camera's tf only when an
image arrives there; published once, a camera on a moving pan/tilt head keeps rendering from its
first pose. This node re-publishes each placeholder at ``~rate`` (Hz, wall) so that every frame
is rendered from the current pose. Remove it when the renderer re-sends the placeholder itself."""
import threading
import time

import rospy
import rosgraph
from sensor_msgs.msg import Image


class RenderRefresh(object):
    def __init__(self, prefix="/camera_renderer/", rate=20.0):
        self.prefix = prefix
        self.rate = rate
        self.lock = threading.Lock()
        self.latest = {}
        self.pubs = {}
        self.subs = {}

    def discover(self):
        try:
            topics = rosgraph.Master(rospy.get_name()).getPublishedTopics("")
        except (IOError, rosgraph.MasterError):
            return
        for name, kind in topics:
            if name.startswith(self.prefix) and name.endswith("/image") and name not in self.subs:
                self.subs[name] = rospy.Subscriber(name, Image, self._store, callback_args=name, queue_size=1)
                self.pubs[name] = rospy.Publisher(name, Image, queue_size=1)

    def _store(self, msg, topic):
        if msg.width == 1 and msg.height == 1:          # the placeholder, not a rendered image
            with self.lock:
                self.latest[topic] = msg

    def run(self):
        next_discovery = 0.0
        while not rospy.is_shutdown():
            if time.monotonic() >= next_discovery:
                self.discover()
                next_discovery = time.monotonic() + 2.0
            with self.lock:
                items = list(self.latest.items())
            for topic, msg in items:
                self.pubs[topic].publish(msg)
            try:
                rospy.rostime.wallsleep(1.0 / self.rate)
            except rospy.ROSInterruptException:
                return


def main():
    rospy.init_node("render_refresh")
    RenderRefresh(rospy.get_param("~prefix", "/camera_renderer/"),
                  float(rospy.get_param("~rate", 20.0))).run()
    return 0
