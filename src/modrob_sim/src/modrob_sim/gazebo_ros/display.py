"""Is there an X display to open a window on? (pure; gzclient's GUI starts only if so)

Gazebo's gzclient without a display fails; a headless machine (CI, SSH without X forwarding)
should get one warning and the simulation should run on. ``connect_display(env)`` returns an open
connection to the X server that ``env['DISPLAY']`` names, or why there is none, in words.

A caller that starts a GUI next keeps the connection open until the GUI has ended: a bare X
server (Xvfb without ``-noreset``) resets when its last client leaves, and a client connecting
during that reset fails (gui_process.py).
"""
import os
import re
import socket

X_SOCKET_DIR = "/tmp/.X11-unix"


def connect_display(env=None, timeout=1.0):
    """``(socket, None)`` connected to the X server of ``env['DISPLAY']``, or ``(None, problem)``."""
    env = os.environ if env is None else env
    display = env.get("DISPLAY", "")
    if not display:
        return None, "DISPLAY is not set"
    m = re.match(r"^(?P<host>[^:]*):(?P<num>\d+)(\.\d+)?$", display)
    if m is None:
        return None, "DISPLAY=%s is not of the form [host]:number" % display
    host, num = m.group("host"), int(m.group("num"))
    try:
        if host in ("", "unix"):
            s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            try:
                s.settimeout(timeout)
                s.connect(os.path.join(X_SOCKET_DIR, "X%d" % num))
            except OSError:
                s.close()
                raise
        else:
            s = socket.create_connection((host, 6000 + num), timeout=timeout)
    except OSError as exc:
        return None, "DISPLAY=%s accepts no connection (%s)" % (display, exc.strerror or exc)
    return s, None
