"""The twist_mux node's ROS side: ``~topics`` and ``~locks`` read, one subscriber per entry in the
node's namespace, ``cmd_vel_out`` published, the state on ``/diagnostics`` every second.
Callbacks hand messages to the pure TwistMux under a lock (rospy runs each subscription in its
own thread)."""
import threading

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Twist
from std_msgs.msg import Bool

from twist_mux.mux import ConfigError, TwistMux, parse_entries

DIAGNOSTICS_PERIOD = 1.0        # s, as twist_mux


class TwistMuxNode(object):
    def __init__(self, topics, locks):
        self.mux = TwistMux(topics, locks)
        for w in self.mux.warnings:
            rospy.logwarn("twist_mux: %s" % w)
        self._lock = threading.Lock()
        self.pub = rospy.Publisher("cmd_vel_out", Twist, queue_size=1)
        self.subs = []
        for v in self.mux.velocities.values():
            self.subs.append(rospy.Subscriber(v.topic, Twist, self._on_twist, v.name, queue_size=1))
            rospy.loginfo("twist_mux: topic %s" % v.describe())
        for lk in self.mux.locks.values():
            self.subs.append(rospy.Subscriber(lk.topic, Bool, self._on_lock, lk.name, queue_size=1))
            rospy.loginfo("twist_mux: lock %s" % lk.describe())
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        self.diag_timer = rospy.Timer(rospy.Duration(DIAGNOSTICS_PERIOD), self._diagnostics, reset=True)
        if not self.mux.velocities:
            rospy.logerr("twist_mux: no velocity topics: set ~topics (a list of {name, topic, timeout, "
                         "priority}, e.g. rosparam load config/twist_mux_topics.yaml into this node)")

    def _on_twist(self, msg, name):
        with self._lock:
            out = self.mux.on_twist(name, msg, rospy.get_time())
        if out is not None:
            self.pub.publish(out)

    def _diagnostics(self, event):
        """Every DIAGNOSTICS_PERIOD: which inputs are masked, which locks locked (as twist_mux's
        diagnostic_updater task 'Twist mux status')."""
        with self._lock:
            values = self.mux.status(rospy.get_time())
        status = DiagnosticStatus(level=DiagnosticStatus.OK,
                                  name="%s: Twist mux status" % rospy.get_name().lstrip("/"), message="ok",
                                  hardware_id="none", values=[KeyValue(k, v) for k, v in values])
        msg = DiagnosticArray(status=[status])
        msg.header.stamp = rospy.Time.now()
        self.diag_pub.publish(msg)

    def _on_lock(self, msg, name):
        with self._lock:
            self.mux.on_lock(name, msg.data, rospy.get_time())


def read_config():
    """(topics, locks) from ``~topics`` and ``~locks``; a malformed list is reported and left out."""
    out = []
    for key in ("topics", "locks"):
        param = rospy.resolve_name("~" + key)
        try:
            out.append(parse_entries(rospy.get_param("~" + key, None), param))
        except ConfigError as err:
            rospy.logerr("twist_mux: %s; the %s are left out until the parameter is fixed and the node "
                         "restarted" % (err, key))
            out.append([])
    return out
