"""``rosrun rqt_plot rqt_plot /topic/field[index] ... [--window S] [--duration S] [--png F]
[--csv F] [--no-gui]``: plot live; on exit (window closed, Ctrl-C, or --duration seconds of ROS
time recorded) write the PNG (what the window shows) and the CSV (every sample)."""
import argparse
import signal
import sys
import threading
import time

import rosgraph
import rospy

from rqt_plot.errors import PlotError
from rqt_plot.recorder import PlotRecorder
from rqt_plot.series import SeriesStore, write_csv, write_png


def parse_args(argv):
    p = argparse.ArgumentParser(prog="rqt_plot", description="Live plots of numeric message fields.")
    p.add_argument("series", nargs="*", help="/topic/field[index] or /topic/a:b, e.g. "
                                             "/ptrz/pan_position_controller/state/process_value")
    p.add_argument("--window", type=float, default=10.0,
                   help="rolling window in seconds of ROS time (0 = everything; default 10)")
    p.add_argument("--duration", type=float, default=0.0,
                   help="stop after this many seconds of ROS time since the first sample (0 = until closed)")
    p.add_argument("--png", help="write the plot here on exit")
    p.add_argument("--csv", help="write every sample here on exit (time,series,value)")
    p.add_argument("--title", default="", help="plot title")
    p.add_argument("--no-gui", action="store_true",
                   help="record without a window (needs --duration or Ctrl-C)")
    args = p.parse_args(argv)
    if args.window < 0 or args.duration < 0:
        p.error("--window and --duration must be >= 0")
    if args.no_gui and not args.series:
        p.error("--no-gui needs at least one series")
    return args


def save(store, args):
    for path, writer in ((args.csv, lambda p: write_csv(store, p)),
                         (args.png, lambda p: write_png(store, p, args.window, args.title))):
        if path:
            writer(path)
            print("rqt_plot: %d samples -> %s" % (store.count(), path))


def main(argv=None):
    args = parse_args(rospy.myargv(sys.argv if argv is None else argv)[1:])
    if not rosgraph.is_master_online():
        sys.stderr.write("rqt_plot: no ROS master at %s: start roscore or a scenario first\n"
                         % rosgraph.get_master_uri())
        return 2
    rospy.init_node("rqt_plot", anonymous=True, disable_signals=True)
    store = SeriesStore([])
    stop = threading.Event()
    messages = []

    def say(text):
        messages.append(text)
        sys.stderr.write("rqt_plot: %s\n" % text)

    recorder = PlotRecorder(store, lambda text: say(text))
    try:
        recorder.add(*args.series)
    except PlotError as err:
        sys.stderr.write("rqt_plot: %s\n" % err)
        return 2
    if args.series and not store.names:          # every series was refused
        return 2
    signal.signal(signal.SIGINT, lambda *_: stop.set())

    def done():
        return stop.is_set() or rospy.is_shutdown() or (args.duration > 0 and store.span() >= args.duration)

    if args.no_gui:
        while not done():
            time.sleep(0.05)
    else:
        from PyQt5 import QtCore, QtWidgets
        from rqt_plot.plot_window import PlotWindow
        app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
        window = PlotWindow(store, recorder.add, args.window, args.title)
        recorder.on_message = window.bridge.message.emit
        for text in messages:
            window.show_message(text)
        window.show()
        poll = QtCore.QTimer()
        poll.timeout.connect(lambda: done() and app.quit())
        poll.start(50)
        app.exec_()
        window.timer.stop()
    recorder.close()
    if args.duration > 0:
        store.trim(args.duration)
    try:
        save(store, args)
    except PlotError as err:
        sys.stderr.write("rqt_plot: %s\n" % err)
        return 2
    rospy.signal_shutdown("done")
    return 2 if recorder.failed else 0
