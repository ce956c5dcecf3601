"""``rosrun rqt_reconfigure rqt_reconfigure [server ...] [--filter TEXT] [--screenshot PNG]``:
the node, the Qt application and the window. Servers named on the command line open at start."""
import argparse
import signal
import sys

import rosgraph
import rospy
from PyQt5 import QtCore, QtWidgets

from rqt_reconfigure.main_window import ReconfigureWindow
from rqt_reconfigure.ros_servers import ServerConnection, list_servers


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="rqt_reconfigure",
                                     description="Edit dynamic_reconfigure servers live.")
    parser.add_argument("servers", nargs="*",
                        help="servers to open at start, e.g. /ptrz/pan_position_controller/pid")
    parser.add_argument("--filter", default="", help="text for the filter box (e.g. a robot namespace)")
    parser.add_argument("--screenshot", metavar="PNG",
                        help="save the window to PNG once the named servers show their values, then quit")
    parser.add_argument("--timeout", type=float, default=20.0,
                        help="seconds --screenshot waits for the servers (default 20)")
    return parser.parse_args(rospy.myargv(argv)[1:])


def _screenshot_when_ready(app, window, path, deadline):
    ready = window.panels and all(p.editors and p._last_config is not None for p in window.panels.values())
    if ready or QtCore.QDateTime.currentMSecsSinceEpoch() > deadline:
        if not ready:
            sys.stderr.write("rqt_reconfigure: servers %s did not show their values in time; saving anyway\n"
                             % ", ".join(window.panels))
        app.processEvents()
        window.grab().save(path)
        print("rqt_reconfigure: window saved to %s" % path)
        app.exit(0 if ready else 1)
        return
    QtCore.QTimer.singleShot(200, lambda: _screenshot_when_ready(app, window, path, deadline))


def main(argv=None):
    args = parse_args(sys.argv if argv is None else argv)
    if not rosgraph.is_master_online():
        sys.stderr.write("rqt_reconfigure: no ROS master at %s: start roscore or a scenario first\n"
                         % rosgraph.get_master_uri())
        return 2
    rospy.init_node("rqt_reconfigure", anonymous=True, disable_signals=True)
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    window = ReconfigureWindow(list_servers, ServerConnection)
    window.filter.setText(args.filter)
    window.refresh()
    for name in args.servers:
        window.open_server(name if name.startswith("/") else "/" + name)
    window.show()
    signal.signal(signal.SIGINT, lambda *_: app.quit())
    tick = QtCore.QTimer()
    tick.timeout.connect(lambda: None)      # lets Python see Ctrl-C while Qt runs
    tick.start(200)
    if args.screenshot:
        deadline = QtCore.QDateTime.currentMSecsSinceEpoch() + int(args.timeout * 1000)
        _screenshot_when_ready(app, window, args.screenshot, deadline)
    code = app.exec_()
    window.close()
    rospy.signal_shutdown("window closed")
    return code
