"""The ROS layer: one snapshot of the computation graph from the master (who publishes and
subscribes what, topic types) and from every node's XML-RPC ``getBusInfo`` (which connections
are live). Nodes are asked in parallel with a short timeout, so a hung node costs one timeout
and is drawn from its registrations alone."""
import concurrent.futures
import http.client
import socket
import xmlrpc.client

import rosgraph

from rqt_graph.errors import GraphError
from rqt_graph.graph_model import SystemSnapshot


class _TimeoutTransport(xmlrpc.client.Transport):
    def __init__(self, timeout):
        xmlrpc.client.Transport.__init__(self)
        self.timeout = timeout

    def make_connection(self, host):
        conn = xmlrpc.client.Transport.make_connection(self, host)
        conn.timeout = self.timeout
        return conn


def _bus_info(caller_id, uri, timeout):
    """The node's live outbound connections [(topic, destination node)], or None."""
    try:
        proxy = xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport(timeout))
        code, _msg, info = proxy.getBusInfo(caller_id)
    except (OSError, socket.timeout, xmlrpc.client.Error, http.client.HTTPException, ValueError):
        return None
    if code != 1:
        return None
    out = []
    for entry in info:
        # (connection id, destination, direction, transport, topic, connected[, info])
        if len(entry) >= 5 and entry[2] == "o" and (len(entry) < 6 or entry[5]):
            out.append((entry[4], entry[1]))
    return out


def snapshot(caller_id="/rqt_graph", bus_info=True, timeout=1.0):
    """A SystemSnapshot of the running system; GraphError when the master does not answer."""
    master = rosgraph.Master(caller_id)
    try:
        pubs, subs, _srvs = master.getSystemState()
        types = dict(master.getTopicTypes())
    except (OSError, rosgraph.masterapi.Error, rosgraph.masterapi.Failure) as err:
        raise GraphError("cannot ask the master at %s (is roscore running? ROS_MASTER_URI right?): %s"
                         % (rosgraph.get_master_uri(), err))
    publishers = {t: n for t, n in pubs}
    subscribers = {t: n for t, n in subs}
    snap = SystemSnapshot(publishers, subscribers, types)
    if not bus_info:
        return snap
    uris = {}
    for node in snap.nodes:
        try:
            uris[node] = master.lookupNode(node)
        except (OSError, rosgraph.masterapi.Error, rosgraph.masterapi.Failure):
            continue
    infos = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=8) as pool:
        futures = {node: pool.submit(_bus_info, caller_id, uri, timeout) for node, uri in uris.items()}
        for node, fut in futures.items():
            conns = fut.result()
            if conns is not None:
                infos[node] = conns
    return SystemSnapshot(publishers, subscribers, types, infos, snap.nodes)
