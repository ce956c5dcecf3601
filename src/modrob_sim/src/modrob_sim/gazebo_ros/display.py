"""Is there an X display to open a window on? (pure; gzclient's GUI starts only if so)

Gazebo's gzclient without a display fails; a headless machine (CI, SSH without X forwarding)
should get one warning and the simulation should run on. ``display_problem(env)`` returns None when
``env['DISPLAY']`` names a display that accepts connections, else why not, in words.
"""
import os
import re
import socket

X_SOCKET_DIR = "/tmp/.X11-unix"


def display_problem(env=None, timeout=1.0):
    env = os.environ if env is None else env
    display = env.get("DISPLAY", "")
    if not display:
        return "DISPLAY is not set"
    m = re.match(r"^(?P<host>[^:]*):(?P<num>\d+)(\.\d+)?$", display)
    if m is None:
        return "DISPLAY=%s is not of the form [host]:number" % display
    host, num = m.group("host"), int(m.group("num"))
    try:
        if host in ("", "unix"):
            path = os.path.join(X_SOCKET_DIR, "X%d" % num)
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
                s.settimeout(timeout)
                s.connect(path)
        else:
            with socket.create_connection((host, 6000 + num), timeout=timeout):
                pass
    except OSError as exc:
        return "DISPLAY=%s accepts no connection (%s)" % (display, exc.strerror or exc)
    return None
