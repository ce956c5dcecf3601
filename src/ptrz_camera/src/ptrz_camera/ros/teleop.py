"""keyboard_joint_control: the seed's keyboard teleop (ptrz_camera.keymap) on a terminal."""
import os
import select
import signal
import sys
import termios

import rospy
from std_msgs.msg import Float64

from ptrz_camera import keymap, zoom
from ptrz_camera.errors import TerminalError


class Terminal(object):
    """Reads single keys from a terminal. While the teleop runs, the terminal is in a raw-like
    mode (no line buffering, no echo, Ctrl-C arrives as a key, as in the seed's raw reads; output
    processing kept so that printed lines stay readable); :meth:`close` restores the settings it
    found, whatever happened. Keys typed between two reads are kept (the seed switched modes
    with TCSAFLUSH around every read, which dropped them)."""

    def __init__(self, stream=sys.stdin):
        self.stream = stream
        if not stream.isatty():
            raise TerminalError("keyboard_joint_control needs a terminal on stdin (run it with rosrun in a "
                                "shell, not with roslaunch or a pipe)")
        self.fd = stream.fileno()
        self.settings = termios.tcgetattr(self.fd)
        mode = termios.tcgetattr(self.fd)
        mode[0] &= ~(termios.IXON | termios.ICRNL | termios.INLCR | termios.IGNCR)
        mode[3] &= ~(termios.ICANON | termios.ECHO | termios.ISIG | termios.IEXTEN)
        mode[6][termios.VMIN] = 1
        mode[6][termios.VTIME] = 0
        termios.tcsetattr(self.fd, termios.TCSANOW, mode)

    def get_key(self, timeout=0.1):
        ready, _, _ = select.select([self.fd], [], [], timeout)
        return os.read(self.fd, 1).decode("utf-8", "replace") if ready else ""

    def close(self):
        termios.tcsetattr(self.fd, termios.TCSADRAIN, self.settings)


class KeyboardTeleop(object):
    def __init__(self, ns, fov, fov_min, fov_max, terminal):
        self.ns = ns.rstrip("/") or "/"
        self.state = keymap.TeleopState(fov=fov, fov_range=(fov_min, fov_max), ns=self.ns)
        self.terminal = terminal
        self.pubs = [rospy.Publisher("%s/%s_position_controller/command" % (self.ns, j), Float64,
                                     queue_size=10) for j in keymap.JOINTS]
        self.zoom_pub = rospy.Publisher(self.ns + "/zoom", Float64, queue_size=1, latch=True)

    def publish(self):
        for pub, value in zip(self.pubs, self.state.commands()):
            pub.publish(Float64(value))

    def run(self):
        print(keymap.help_text(self.ns))
        while not rospy.is_shutdown() and not self.state.quit:
            lines = self.state.press(self.terminal.get_key())
            if lines:
                print("\n".join(lines))
            sys.stdout.flush()
            if self.state.quit:
                break        # the camera holds its last targets: nothing is sent on exit
            if self.state.zoom_changed:
                self.zoom_pub.publish(Float64(self.state.fov))
            self.publish()


def main():
    try:
        terminal = Terminal()
    except TerminalError as exc:
        sys.stderr.write("%s\n" % exc)
        return 2
    try:
        rospy.init_node("ptrz_key_teleop", disable_signals=True)
    except BaseException:
        terminal.close()
        raise
    ns = rospy.get_param("~ns", "/ptrz")
    fov = rospy.get_param("~fov", zoom.NOMINAL_FOV)
    fov_min = rospy.get_param("~fov_min", zoom.TELE_FOV)
    fov_max = rospy.get_param("~fov_max", zoom.WIDE_FOV)
    signal.signal(signal.SIGTERM, lambda *_: rospy.signal_shutdown("SIGTERM"))
    try:
        KeyboardTeleop(ns, fov, fov_min, fov_max, terminal).run()
    except KeyboardInterrupt:
        pass
    finally:
        terminal.close()
        rospy.signal_shutdown("teleop finished")
    return 0
