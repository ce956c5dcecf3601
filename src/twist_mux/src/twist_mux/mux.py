"""twist_mux's rules, pure (no rospy; time is passed in, seconds of ROS time).

* Each velocity input has a name, a topic, a ``timeout`` (s; 0 = never stale, even before its
  first message) and a ``priority``
  (0..255, clamped). It is *masked* when stale or when its priority is below the highest priority
  of the locks that are locked.
* Each lock has the same fields; it is *locked* while its last std_msgs/Bool was true, or while it
  is stale (a lock with a timeout is a heartbeat: silence locks; it starts locked until its first
  message). A lock with timeout 0 only locks on ``true``.
* A twist arriving on an input is passed on unchanged when that input is, at that moment, the
  unmasked input of highest priority (on equal priorities the first in the list). Nothing is
  published otherwise, and nothing is repeated: when the selected input falls silent the output
  falls silent too (the base controller's own command timeout then stops the robot).
"""
from collections import OrderedDict

PRIORITY_MIN, PRIORITY_MAX = 0, 255
KEYS = ("name", "topic", "timeout", "priority")


class ConfigError(ValueError):
    """A malformed ``topics``/``locks`` entry; the message names the parameter and the entry."""


class Input(object):
    def __init__(self, name, topic, timeout, priority):
        self.name, self.topic = name, topic
        self.timeout = float(timeout)
        self.priority = min(max(int(priority), PRIORITY_MIN), PRIORITY_MAX)
        self.stamp = None            # ROS time of the last message; None: none yet
        self.value = None

    def receive(self, value, now):
        self.value, self.stamp = value, now

    def expired(self, now):
        return self.timeout > 0.0 and (self.stamp is None or now - self.stamp > self.timeout)

    def describe(self):
        return "'%s' on %s (timeout %s, priority %d)" % (
            self.name, self.topic, "%gs" % self.timeout if self.timeout else "none", self.priority)


class VelocityInput(Input):
    def masked(self, now, lock_priority):
        return self.expired(now) or self.priority < lock_priority


class LockInput(Input):
    def locked(self, now):
        return self.expired(now) or bool(self.value)


def parse_entries(entries, param):
    """The list under ``~topics`` or ``~locks`` -> [(name, topic, timeout, priority)].
    twist_mux also accepted a dictionary keyed by name in older releases: accepted too."""
    if entries is None:
        return []
    if isinstance(entries, dict):
        entries = [dict(v, name=v.get("name", k)) if isinstance(v, dict) else v for k, v in entries.items()]
    if not isinstance(entries, list):
        raise ConfigError("%s must be a list of {name, topic, timeout, priority}, got %r" % (param, entries))
    out = []
    for i, e in enumerate(entries):
        where = "%s[%d]" % (param, i)
        if not isinstance(e, dict):
            raise ConfigError("%s must be a dictionary {name, topic, timeout, priority}, got %r" % (where, e))
        missing = [k for k in KEYS if k not in e]
        if missing:
            raise ConfigError("%s (%s) lacks %s: every entry needs name, topic, timeout and priority"
                              % (where, e.get("name", "?"), ", ".join(missing)))
        name, topic, timeout, priority = (e[k] for k in KEYS)
        if not isinstance(name, str) or not name or not isinstance(topic, str) or not topic:
            raise ConfigError("%s: name and topic must be non-empty strings, got %r and %r"
                              % (where, name, topic))
        if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or not timeout >= 0.0:
            raise ConfigError("%s (%s): timeout must be a number of seconds >= 0 (0 = never stale), got %r"
                              % (where, name, timeout))
        if isinstance(priority, bool) or not isinstance(priority, int):
            raise ConfigError("%s (%s): priority must be a whole number 0..255, got %r"
                              % (where, name, priority))
        out.append((name, topic, float(timeout), priority))
    return out


class TwistMux(object):
    def __init__(self, topics, locks):
        """``topics``, ``locks``: [(name, topic, timeout, priority)]."""
        self.velocities = OrderedDict()
        self.locks = OrderedDict()
        self.warnings = []
        for table, cls, entries in ((self.velocities, VelocityInput, topics), (self.locks, LockInput, locks)):
            for name, topic, timeout, priority in entries:
                if name in table:
                    self.warnings.append("two entries are named '%s': the second (%s) is ignored; give each "
                                         "a name of its own" % (name, topic))
                    continue
                if not PRIORITY_MIN <= priority <= PRIORITY_MAX:
                    self.warnings.append("'%s': priority %d clamped to %d..%d"
                                         % (name, priority, PRIORITY_MIN, PRIORITY_MAX))
                table[name] = cls(name, topic, timeout, priority)

    def lock_priority(self, now):
        return max([lk.priority for lk in self.locks.values() if lk.locked(now)] or [0])

    def selected(self, now):
        """The velocity input that would be passed on now, or None."""
        lock = self.lock_priority(now)
        best, best_priority = None, 0
        for v in self.velocities.values():
            # as twist_mux: strictly above the best so far, starting from 0
            if not v.masked(now, lock) and v.priority > best_priority:
                best, best_priority = v, v.priority
        return best

    def on_twist(self, name, msg, now):
        """A twist on input ``name``: returns it when it is to be published, else None."""
        v = self.velocities[name]
        v.receive(msg, now)
        return msg if self.selected(now) is v else None

    def on_lock(self, name, value, now):
        self.locks[name].receive(bool(value), now)

    def status(self, now):
        """twist_mux's diagnostic values: [(key, value)] per input and lock, and the lock priority."""
        lock = self.lock_priority(now)
        out = []
        for v in self.velocities.values():
            out.append(("velocity " + v.name, "%s (listening to %s @ %gs with priority #%d)"
                        % ("masked" if v.masked(now, lock) else "unmasked", v.topic, v.timeout, v.priority)))
        for lk in self.locks.values():
            out.append(("lock " + lk.name, "%s (listening to %s @ %gs with priority #%d)"
                        % ("locked" if lk.locked(now) else "free", lk.topic, lk.timeout, lk.priority)))
        out.append(("current priority", str(lock)))
        return out
