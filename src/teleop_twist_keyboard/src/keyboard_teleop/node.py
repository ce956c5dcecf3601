"""The ROS and terminal side of teleop_twist_keyboard: a publishing thread (each new command at
once, and again at ``repeat_rate`` when set), single keys read from a raw terminal with the key
timeout, the terminal restored and a zero twist published however the node ends."""
import contextlib
import select
import sys
import termios
import threading
import tty
import warnings

import rospy
from geometry_msgs.msg import Twist, TwistStamped


class Publisher(object):
    def __init__(self, rate, stamped=False, frame_id=""):
        self.stamped, self.frame_id = stamped, frame_id
        # synchronous (no queue_size): only this object's own thread publishes, and a queued
        # message still waiting in rospy's connection thread when the node shuts down is dropped,
        # which lost the zero twist on the way out on a loaded machine
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SyntaxWarning)      # rospy's advice for the queued kind
            self.pub = rospy.Publisher("cmd_vel", TwistStamped if stamped else Twist, queue_size=None)
        self.timeout = 1.0 / rate if rate > 0.0 else None
        self.cond = threading.Condition()
        self.value = (0.0, 0.0, 0.0, 0.0)
        self.fresh = False
        self.done = False
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def wait_for_subscribers(self, say):
        """Until someone subscribes (teleop_twist_keyboard waits too), saying so every 2.5 s."""
        n = 0
        while not rospy.is_shutdown() and self.pub.get_num_connections() == 0:
            if n % 5 == 4:
                say("Waiting for subscriber to connect to %s" % self.pub.resolved_name)
            rospy.sleep(0.5)
            n += 1

    def update(self, value):
        with self.cond:
            self.value, self.fresh = value, True
            self.cond.notify()

    def _message(self, value):
        msg = TwistStamped() if self.stamped else Twist()
        twist = msg.twist if self.stamped else msg
        if self.stamped:
            msg.header.stamp, msg.header.frame_id = rospy.Time.now(), self.frame_id
        twist.linear.x, twist.linear.y, twist.linear.z, twist.angular.z = value
        return msg

    def _run(self):
        while True:
            with self.cond:
                if not self.fresh and not self.done:
                    self.cond.wait(self.timeout)
                if self.done:
                    break
                value, self.fresh = self.value, False
            self.pub.publish(self._message(value))
        self.pub.publish(self._message((0.0, 0.0, 0.0, 0.0)))      # stop the robot on the way out

    def stop(self):
        with self.cond:
            self.done = True
            self.cond.notify()
        self.thread.join()


@contextlib.contextmanager
def raw_terminal(stream):
    """Single key presses from ``stream`` (a tty); its settings restored on the way out, whatever
    happens. Not a tty (piped input): read as it comes."""
    fd = stream.fileno()
    saved = termios.tcgetattr(fd) if stream.isatty() else None
    try:
        if saved is not None:
            tty.setraw(fd)
        yield
    finally:
        if saved is not None:
            termios.tcsetattr(fd, termios.TCSADRAIN, saved)


def read_key(stream, timeout):
    """One character, or '' when none came within ``timeout`` seconds (None: wait)."""
    ready, _w, _x = select.select([stream], [], [], timeout)
    if not ready:
        return ""
    ch = stream.read(1)
    return ch if ch else "\x03"            # end of input ends the node like Ctrl-C


def say(text):
    """Print in raw mode: lines need a carriage return."""
    sys.stdout.write(text.replace("\n", "\r\n") + "\r\n")
    sys.stdout.flush()
