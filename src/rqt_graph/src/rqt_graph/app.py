"""``rosrun rqt_graph rqt_graph [-o FILE ...] [options]``: with output files, draw the running
system to them and exit; otherwise (or with --gui) show it in a window."""
import argparse
import signal
import sys
import time

from rqt_graph import render
from rqt_graph.errors import GraphError
from rqt_graph.graph_model import MODES, Options, build_graph, to_dot
from rqt_graph.ros_graph import snapshot


def parse_args(argv):
    p = argparse.ArgumentParser(prog="rqt_graph", description="Draw the running ROS computation graph.")
    p.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                   help="write the graph to FILE (.png .svg .pdf .dot); repeatable; no window unless --gui")
    p.add_argument("--gui", action="store_true", help="open the window even when writing files")
    p.add_argument("--mode", choices=MODES, default="nodes_topics",
                   help="nodes_topics: nodes (ellipses) and topics (boxes); nodes: node -> node edges "
                        "labelled with the topic (default nodes_topics)")
    p.add_argument("--group-namespaces", action="store_true", help="draw each namespace as a box")
    p.add_argument("--show-debug", action="store_true", help="show /rosout and its topics")
    p.add_argument("--hide-tf", action="store_true", help="hide /tf and /tf_static")
    p.add_argument("--hide-leaf-topics", action="store_true",
                   help="hide topics with publishers only or subscribers only")
    p.add_argument("--hide-dead-sinks", action="store_true", help="hide topics nobody publishes")
    p.add_argument("--hide-params", action="store_true",
                   help="hide dynamic_reconfigure's parameter_descriptions/parameter_updates topics")
    p.add_argument("--filter", default="", help="words a node/topic name must contain; -word hides")
    p.add_argument("--settle", type=float, default=0.0, metavar="S",
                   help="first wait until the set of nodes and topics has not changed for S seconds "
                        "(at most 120 s): for a system that is still starting")
    p.add_argument("--no-bus-info", action="store_true",
                   help="do not ask each node for its live connections (registrations only)")
    args = p.parse_args(argv)
    for path in args.output:
        if not path.lower().endswith(tuple(render.FORMATS)):
            p.error("output '%s' must end in one of %s" % (path, " ".join(sorted(render.FORMATS))))
    return args


def settle(seconds, limit=120.0, period=0.5):
    """Wait until the master's nodes and topics stay the same for ``seconds`` (wall time)."""
    start = last_change = time.monotonic()
    seen = None
    while time.monotonic() - start < limit:
        snap = snapshot(bus_info=False)
        now = (tuple(snap.nodes), tuple(sorted(set(snap.publishers) | set(snap.subscribers))))
        if now != seen:
            seen, last_change = now, time.monotonic()
        elif time.monotonic() - last_change >= seconds:
            return
        time.sleep(period)
    sys.stderr.write("rqt_graph: the graph still changed after %.0f s; drawing it as it is\n" % limit)


def main(argv=None):
    import rospy
    args = parse_args(rospy.myargv(sys.argv if argv is None else argv)[1:])
    opts = Options(mode=args.mode, group_namespaces=args.group_namespaces, hide_debug=not args.show_debug,
                   hide_tf=args.hide_tf, hide_leaf_topics=args.hide_leaf_topics,
                   hide_dead_sinks=args.hide_dead_sinks, hide_params=args.hide_params, filter=args.filter)

    def take():
        return snapshot(bus_info=not args.no_bus_info)

    try:
        if args.settle > 0:
            settle(args.settle)
        if args.output:
            graph = build_graph(take(), opts)
            dot = to_dot(graph, opts)
            for path in args.output:
                render.write(dot, path)
                print("rqt_graph: %d nodes, %d topics, %d edges -> %s"
                      % (len(graph.nodes), len(graph.topics), len(graph.edges), path))
            if not args.gui:
                return 0
    except GraphError as err:
        sys.stderr.write("rqt_graph: %s\n" % err)
        return 2
    from PyQt5 import QtCore, QtWidgets
    from rqt_graph.graph_window import GraphWindow
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    window = GraphWindow(take, opts)
    window.show()
    window.refresh()
    signal.signal(signal.SIGINT, lambda *_: app.quit())
    tick = QtCore.QTimer()
    tick.timeout.connect(lambda: None)      # lets Python see Ctrl-C while Qt runs
    tick.start(200)
    return app.exec_()
