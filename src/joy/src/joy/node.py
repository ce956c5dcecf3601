"""joy_node's ROS and device side: find and open the joystick (by ``~dev`` or by name with
``~dev_name``), waiting for it with one message and a retry every second; read its events,
publish sensor_msgs/Joy on ``joy`` (buttons at once, axes coalesced, repeated at
``~autorepeat_rate``); reopen when the device goes away."""
import array
import fcntl
import glob
import os
import select
import threading
import time

import rospy
from sensor_msgs.msg import Joy

from joy.joystick import JoyState, check_deadzone, decode

JSIOCGNAME_128 = (2 << 30) | (128 << 16) | (ord("j") << 8) | 0x13     # _IOC(_IOC_READ, 'j', 0x13, 128)


def device_name(path):
    """The joystick's name as the kernel reports it, or None (not a joystick, no access)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError:
        return None
    try:
        buf = array.array("B", [0] * 128)
        fcntl.ioctl(fd, JSIOCGNAME_128, buf)
        return buf.tobytes().split(b"\0", 1)[0].decode(errors="replace")
    except OSError:
        return None
    finally:
        os.close(fd)


def find_by_name(name, log):
    """The first /dev/input/js* whose name is ``name`` (each one found is logged), or None."""
    for path in sorted(glob.glob("/dev/input/js*")):
        found = device_name(path)
        if found is not None:
            log("Found joystick: %s (%s)." % (found, path))
            if found == name:
                return path
    return None


class JoyNode(object):
    def __init__(self, dev, dev_name="", deadzone=0.05, autorepeat_rate=0.0, coalesce_interval=0.001,
                 sticky_buttons=False, default_trig_val=False):
        self.dev = dev
        if dev_name:
            found = find_by_name(dev_name, rospy.loginfo)
            if found is None:
                rospy.logerr("Couldn't find a joystick with name %s. Falling back to default device."
                             % dev_name)
            else:
                rospy.loginfo("Using %s as joystick device." % found)
                self.dev = found
        self.deadzone = check_deadzone(deadzone, rospy.logwarn)
        if autorepeat_rate < 0:
            rospy.logwarn("joy_node: autorepeat_rate (%g) less than 0, setting to 0." % autorepeat_rate)
            autorepeat_rate = 0.0
        if coalesce_interval < 0:
            rospy.logwarn("joy_node: coalesce_interval (%g) less than 0, setting to 0." % coalesce_interval)
            coalesce_interval = 0.0
        if autorepeat_rate > 0 and coalesce_interval > 0 and autorepeat_rate > 1.0 / coalesce_interval:
            rospy.logwarn("joy_node: autorepeat_rate (%g Hz) > 1/coalesce_interval (%g Hz) does not make "
                          "sense. Timing behavior is not well defined."
                          % (autorepeat_rate, 1.0 / coalesce_interval))
        self.autorepeat = 1.0 / autorepeat_rate if autorepeat_rate > 0 else None
        self.coalesce = coalesce_interval
        self.sticky, self.default_trig_val = sticky_buttons, default_trig_val
        self.pub = rospy.Publisher("joy", Joy, queue_size=10)

    def _open(self):
        """Wait until the device opens: one message, then a retry every second. The open itself
        runs in a helper thread, so that a shutdown is not held up by a device whose open blocks
        (a named pipe without a writer)."""
        told = False
        while not rospy.is_shutdown():
            result = {}

            def attempt():
                try:
                    result["fd"] = os.open(self.dev, os.O_RDONLY)
                except OSError as err:
                    result["error"] = err
            opener = threading.Thread(target=attempt, daemon=True)
            opener.start()
            while opener.is_alive() and not rospy.is_shutdown():
                opener.join(0.2)
            if "fd" in result:
                return result["fd"]
            if "error" in result and not told:
                rospy.logerr("Couldn't open joystick %s (%s). Will retry every second."
                             % (self.dev, result["error"].strerror))
                told = True
            if not rospy.is_shutdown():
                time.sleep(1.0)        # joy_node's retry period for a missing device
        return None

    def publish(self, state):
        msg = Joy(axes=list(state.axes), buttons=list(state.buttons))
        msg.header.stamp = rospy.Time.now()
        msg.header.frame_id = self.dev
        self.pub.publish(msg)

    def run(self):
        while not rospy.is_shutdown():
            fd = self._open()
            if fd is None:
                return
            name = device_name(self.dev)
            rospy.loginfo("Opened joystick: %s (%s). deadzone_: %f."
                          % (self.dev, name or "no name", self.deadzone))
            self._serve(fd)
            os.close(fd)
            if not rospy.is_shutdown():
                rospy.logerr("Connection to joystick device lost unexpectedly. Will reopen.")

    def _serve(self, fd):
        state = JoyState(self.deadzone, self.sticky, self.default_trig_val)
        pending = None                      # time by which a coalesced message is due
        last = time.monotonic()
        rest = b""
        while not rospy.is_shutdown():
            now = time.monotonic()
            if pending is not None:
                timeout = max(0.0, pending - now)
            elif self.autorepeat is not None:
                timeout = max(0.0, last + self.autorepeat - now)
            else:
                timeout = 1.0
            ready, _w, _x = select.select([fd], [], [], timeout)
            now = time.monotonic()
            if ready:
                try:
                    data = os.read(fd, 64 * 8)
                except OSError:
                    return
                if not data:
                    return                  # the device (or the pipe's writer) went away
                events, rest = decode(rest + data)
                for ev in events:
                    what = state.apply(ev)
                    if what == "now":
                        pending = None
                        self.publish(state)
                        last = now
                    elif what == "soon" and pending is None:
                        pending = now + self.coalesce
                continue
            if pending is not None and now >= pending:
                pending = None
                self.publish(state)
                last = now
            elif self.autorepeat is not None and now - last >= self.autorepeat:
                self.publish(state)
                last = now
