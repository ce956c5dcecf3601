"""The ROS layer: which dynamic_reconfigure servers the master knows, and one connection per server
that reports its description and every update (made here or elsewhere) and sends changes.

Sending runs in a worker thread with latest-wins merging: dragging a slider queues many values,
the server sees the newest one and the GUI never blocks on a service call."""
import threading

import dynamic_reconfigure
import dynamic_reconfigure.client
import rosgraph
import rospy
import rosservice

from rqt_reconfigure.errors import ReconfigureError
from rqt_reconfigure.param_model import group_from_dict


def list_servers():
    """Names of every dynamic_reconfigure server the master knows (services ending in
    ``/set_parameters``), sorted."""
    try:
        return dynamic_reconfigure.find_reconfigure_services()
    except (rosservice.ROSServiceIOException, rosgraph.masterapi.MasterException) as err:
        raise ReconfigureError("cannot list services from the master at %s (is roscore running?): %s"
                               % (rosgraph.get_master_uri(), err))


class ServerConnection(object):
    """A dynamic_reconfigure client for ``name``.

    ``on_description(GroupSpec)``, ``on_config(dict)`` and ``on_error(str)`` are called from ROS
    threads; the GUI forwards them to its own thread with Qt signals."""

    def __init__(self, name, on_description, on_config, on_error, timeout=5.0):
        self.name = name
        self.on_description = on_description
        self.on_config = on_config
        self.on_error = on_error
        self.timeout = timeout
        self.client = None
        self._pending = {}
        self._cond = threading.Condition()
        self._closed = False
        self._thread = threading.Thread(target=self._run, name="reconfigure %s" % name, daemon=True)
        self._thread.start()

    def set(self, changes):
        """Queue ``changes`` (dict name -> value); later values for a name replace earlier ones."""
        with self._cond:
            self._pending.update(changes)
            self._cond.notify()

    def close(self):
        with self._cond:
            self._closed = True
            self._cond.notify()
        if self.client is not None:
            try:
                self.client.close()
            except rospy.ROSException:
                pass

    def _connect(self):
        try:
            self.client = dynamic_reconfigure.client.Client(self.name, timeout=self.timeout)
        except rospy.ROSException as err:
            self.on_error("no dynamic_reconfigure server at %s (%s); press Refresh" % (self.name, err))
            return False
        groups = self.client.get_group_descriptions(timeout=self.timeout)
        if groups is None:
            self.on_error("%s published no parameter description within %.0f s" % (self.name, self.timeout))
            return False
        try:
            self.on_description(group_from_dict(groups))
        except ReconfigureError as err:
            self.on_error("%s: %s" % (self.name, err))
            return False
        config = self.client.get_configuration(timeout=self.timeout)
        if config is not None:
            self.on_config(dict(config))
        self.client.set_config_callback(self._config_cb)
        return True

    def _config_cb(self, config):
        if config is not None:
            self.on_config(dict(config))

    def _run(self):
        if not self._connect():
            return
        while True:
            with self._cond:
                while not self._pending and not self._closed:
                    self._cond.wait()
                if self._closed:
                    return
                changes, self._pending = self._pending, {}
            try:
                self.client.update_configuration(changes)
            except (rospy.ServiceException, rospy.ROSException,
                    dynamic_reconfigure.DynamicReconfigureParameterException) as err:
                self.on_error("%s rejected %s: %s" % (self.name, changes, err))
