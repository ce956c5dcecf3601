"""The ROS layer: resolve series names against the topics being published, subscribe once per
topic, and store every sample with its time: the message's ``header.stamp`` when it has a
non-zero one (the time the data belongs to, as rqt_plot does), else the ROS time of arrival
(simulated time under use_sim_time). Names whose topic is not published yet are retried every
half second; a field that does not exist is reported once and dropped."""
import threading

import roslib.message
import rospy

from rqt_plot.errors import PlotError
from rqt_plot.field_path import check_path, expand, extract, parse_fields, split_topic


class PlotRecorder(object):
    def __init__(self, store, on_message, queue_size=1000):
        """``on_message(text)``: one line for the user (waiting, errors), from any thread."""
        self.store = store
        self.on_message = on_message
        self.queue_size = queue_size
        self.lock = threading.Lock()
        self.pending = []                 # names not resolved yet
        self.waiting_said = set()
        self.subs = {}                    # topic -> (Subscriber, [(name, fields)])
        self.failed = {}                  # name -> reason
        self._resolving = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._resolve_loop, name="rqt_plot resolve", daemon=True)
        self._thread.start()

    def add(self, *specs):
        """Add each spec (``/topic/field[i]`` or ``/topic/a:b``); returns the series names. The
        specs are resolved together, so that series of one topic start with the same message."""
        names = [name for spec in specs for name in expand(spec.strip())]
        for name in names:
            parse_fields(name.lstrip("/"))     # early syntax check, PlotError on bad text
        for name in names:
            self.store.add_name(name)
            with self.lock:
                self.pending.append(name)
        self._resolve_once()
        return names

    def close(self):
        self._stop.set()
        for sub, _ in list(self.subs.values()):
            sub.unregister()

    def _resolve_loop(self):
        while not self._stop.wait(0.5):
            self._resolve_once()

    def _resolve_once(self):
        with self._resolving:            # add() (caller's thread) and the retry loop take turns
            self._resolve_pending()

    def _resolve_pending(self):
        with self.lock:
            todo = list(self.pending)
        if not todo:
            return
        try:
            published = dict(rospy.get_published_topics())
        except (OSError, rospy.ROSException) as err:
            self.on_message("cannot ask the master for topics: %s" % err)
            return
        resolved = {}                     # topic -> (message class, [(name, fields)])
        for name in todo:
            found = split_topic(name, published)
            if found is None:
                if name not in self.waiting_said:
                    self.waiting_said.add(name)
                    self.on_message("waiting for a publisher of %s" % name)
                continue
            topic, field_text = found
            try:
                fields = parse_fields(field_text)
                cls = roslib.message.get_message_class(published[topic])
                if cls is None:
                    raise PlotError("%s: message type %s is not known here (built and sourced?)"
                                    % (topic, published[topic]))
                check_path(cls, fields, roslib.message.get_message_class, topic)
            except PlotError as err:
                self.failed[name] = str(err)
                self.store.remove_name(name)
                self.on_message(str(err))
                with self.lock:
                    self.pending.remove(name)
                continue
            resolved.setdefault(topic, (cls, []))[1].append((name, fields))
        # subscribe once every field of a topic resolved in this pass is known: fields of one topic
        # added together then have samples from the same messages, none from before the others
        for topic, (cls, targets) in resolved.items():
            with self.lock:
                for name, _fields in targets:
                    self.pending.remove(name)
                if topic in self.subs:
                    self.subs[topic][1].extend(targets)
                else:
                    sub = rospy.Subscriber(topic, cls, self._callback, callback_args=targets,
                                           queue_size=self.queue_size)
                    self.subs[topic] = (sub, targets)
            for name, _fields in targets:
                if name in self.waiting_said:
                    self.on_message("plotting %s" % name)

    def _callback(self, msg, targets):
        stamp = getattr(getattr(msg, "header", None), "stamp", None)
        t = stamp.to_sec() if stamp is not None and not stamp.is_zero() else rospy.get_time()
        for name, fields in list(targets):
            value = extract(msg, fields)
            if value is not None:
                self.store.append(name, t, value)
