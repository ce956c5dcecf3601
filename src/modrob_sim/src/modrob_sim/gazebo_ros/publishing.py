"""Publishing for plugins without slowing the physics thread (docs/plugins.md, "Publishing").

rospy serialises a message in the thread that calls ``publish``. For a JointState that is a few
microseconds; for a PointCloud2 or an Image it is milliseconds, which the simulation loop would
pay every sensor period. :class:`PluginPublisher` offers both:

- ``publish(msg)``: at once, in the calling (loop) thread - for small messages;
- ``publish_later(build)``: ``build()`` is called in the node's one publishing thread
  (:class:`PublishQueue`), which makes the message and publishes it. The hook copies the data it
  needs (the World may change after the hook returns) and passes a closure over the copies.
  Latest wins: a pending build that has not run yet when the next one arrives is dropped
  (counted in ``dropped``), as a ``queue_size=1`` publisher would do under load.

``has_subscribers`` lets a sensor skip its work when nobody listens (latched publishers always
count as listened to).
"""
import collections
import logging
import threading
import traceback

LOG = logging.getLogger("modrob_sim.gazebo_ros.publishing")


class PluginPublisher(object):
    """A rospy publisher (``pub``) with an off-thread path through ``queue`` (a PublishQueue)."""

    def __init__(self, pub, queue, latch=False):
        self.pub = pub
        self._queue = queue
        self._latch = latch
        self.dropped = 0

    @property
    def name(self):
        return self.pub.resolved_name

    @property
    def has_subscribers(self):
        return self._latch or self.pub.get_num_connections() > 0

    def publish(self, msg):
        self.pub.publish(msg)

    def publish_later(self, build):
        """Hand ``build() -> message`` to the publishing thread (latest wins)."""
        if not self._queue.put(self, build):
            self.dropped += 1

    def unregister(self):
        self._queue.forget(self)
        self.pub.unregister()


class PublishQueue(object):
    """The node's publishing thread: runs pending ``build`` calls and publishes their messages,
    one pending build per publisher. Pure (no rospy): ``publish`` is the publisher's own."""

    def __init__(self):
        self._pending = collections.OrderedDict()   # id(publisher) -> (publisher, build)
        self._cond = threading.Condition()
        self._stop = False
        self._thread = threading.Thread(target=self._run, name="plugin_publishing", daemon=True)
        self._thread.start()

    def put(self, publisher, build):
        """Queue ``build`` for ``publisher``; False when it replaced a pending one (dropped)."""
        with self._cond:
            if self._stop:
                return True
            replaced = id(publisher) in self._pending
            self._pending[id(publisher)] = (publisher, build)
            self._cond.notify()
        return not replaced

    def forget(self, publisher):
        with self._cond:
            self._pending.pop(id(publisher), None)

    def stop(self, timeout=2.0):
        with self._cond:
            self._stop = True
            self._pending.clear()
            self._cond.notify_all()
        if self._thread is not threading.current_thread():
            self._thread.join(timeout)

    def _run(self):
        while True:
            with self._cond:
                while not self._pending and not self._stop:
                    self._cond.wait()
                if self._stop:
                    return
                _, (publisher, build) = self._pending.popitem(last=False)
            try:
                msg = build()
                if msg is not None:
                    publisher.pub.publish(msg)
            except Exception as exc:  # noqa: B902 - a faulty build must not stop other publishers
                LOG.error("publishing on %s failed: %s: %s\n%s", publisher.name, type(exc).__name__, exc,
                          traceback.format_exc())


def ros_advertiser(queue):
    """``advertise(topic, msg_class, queue_size, latch)`` for PluginContext: roscpp's transport
    when the node runs it (native_pub), else rospy."""
    from modrob_sim.gazebo_ros.native_pub import publisher

    def advertise(topic, msg_class, queue_size=1, latch=False):
        return PluginPublisher(publisher(topic, msg_class, queue_size=queue_size, latch=latch),
                               queue, latch=latch)
    return advertise
