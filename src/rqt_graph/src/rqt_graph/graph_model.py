"""The pure core of the node graph (no rospy, no Qt): what the master and the nodes said ->
a graph with rqt_graph's filters -> graphviz DOT text.

Inputs are plain data: ``publishers``/``subscribers`` map a topic to the nodes registered on
it (the master's getSystemState), ``types`` a topic to its message type, ``bus_info`` a node
to its live outbound connections ``[(topic, destination node), ...]`` (each node's getBusInfo;
nodes that did not answer are left out)."""
import re

MODES = ("nodes_topics", "nodes")
DEBUG_NODES = ("/rosout",)
DEBUG_TOPICS = ("/rosout", "/rosout_agg", "/statistics")
TF_TOPICS = ("/tf", "/tf_static")
PARAM_SUFFIXES = ("/parameter_descriptions", "/parameter_updates")   # dynamic_reconfigure's topics


class SystemSnapshot(object):
    def __init__(self, publishers, subscribers, types=None, bus_info=None, nodes=None):
        self.publishers = {t: sorted(set(n)) for t, n in publishers.items()}
        self.subscribers = {t: sorted(set(n)) for t, n in subscribers.items()}
        self.types = dict(types or {})
        self.bus_info = {n: sorted(set(c)) for n, c in (bus_info or {}).items()}
        found = set(nodes or [])
        for table in (self.publishers, self.subscribers):
            for names in table.values():
                found.update(names)
        self.nodes = sorted(found)


class Options(object):
    """rqt_graph's check boxes. ``filter``: only nodes/topics whose name contains one of its
    blank-separated words (a leading '-' excludes instead), as rqt_graph's filter fields."""

    def __init__(self, mode="nodes_topics", group_namespaces=False, hide_debug=True, hide_tf=False,
                 hide_leaf_topics=False, hide_dead_sinks=False, hide_params=False, filter="",
                 exclude_nodes=()):
        if mode not in MODES:
            raise ValueError("mode '%s' is not one of %s" % (mode, ", ".join(MODES)))
        self.mode = mode
        self.group_namespaces = group_namespaces
        self.hide_debug = hide_debug
        self.hide_tf = hide_tf
        self.hide_leaf_topics = hide_leaf_topics
        self.hide_dead_sinks = hide_dead_sinks
        self.hide_params = hide_params
        self.filter = filter
        self.exclude_nodes = tuple(exclude_nodes)


class Graph(object):
    """``nodes``/``topics``: sorted names; ``edges``: sorted (source, target, label) where
    source/target are node or topic names (label '' in nodes_topics mode, the topic in nodes
    mode); ``live``: the edges the nodes' bus info confirms."""

    def __init__(self, nodes, topics, edges, live, types):
        self.nodes = sorted(nodes)
        self.topics = sorted(topics)
        self.edges = sorted(edges)
        self.live = set(live)
        self.types = types

    def has_edge(self, source, target):
        return any(e[0] == source and e[1] == target for e in self.edges)


def _wanted(name, words):
    include = [w for w in words if not w.startswith("-")]
    exclude = [w[1:] for w in words if w.startswith("-") and len(w) > 1]
    if any(w in name for w in exclude):
        return False
    return not include or any(w in name for w in include)


def build_graph(snap, opts):
    words = opts.filter.split()
    hidden_nodes = set(opts.exclude_nodes)
    if opts.hide_debug:
        hidden_nodes.update(DEBUG_NODES)
    nodes = {n for n in snap.nodes if n not in hidden_nodes and _wanted(n, words)}
    hidden_topics = set()
    if opts.hide_debug:
        hidden_topics.update(DEBUG_TOPICS)
    if opts.hide_tf:
        hidden_topics.update(TF_TOPICS)
    topics = set(snap.publishers) | set(snap.subscribers)
    pubs = {t: [n for n in snap.publishers.get(t, []) if n in nodes] for t in topics}
    subs = {t: [n for n in snap.subscribers.get(t, []) if n in nodes] for t in topics}
    shown = set()
    for t in topics:
        if t in hidden_topics or not (pubs[t] or subs[t]):
            continue
        if opts.hide_params and t.endswith(PARAM_SUFFIXES):
            continue
        if not _wanted(t, words) and not any(_wanted(n, words) for n in pubs[t] + subs[t]):
            continue
        if opts.hide_dead_sinks and not pubs[t]:
            continue
        if opts.hide_leaf_topics and (not pubs[t] or not subs[t]):
            continue
        shown.add(t)
    live_pairs = {(src, t, dst) for src, conns in snap.bus_info.items() for t, dst in conns}
    edges, live = set(), set()
    if opts.mode == "nodes_topics":
        for t in shown:
            for n in pubs[t]:
                e = (n, t, "")
                edges.add(e)
                if any(p == n and tt == t for p, tt, _ in live_pairs):
                    live.add(e)
            for n in subs[t]:
                e = (t, n, "")
                edges.add(e)
                if any(d == n and tt == t for _, tt, d in live_pairs):
                    live.add(e)
        return Graph(nodes, shown, edges, live, snap.types)
    for t in shown:
        for p in pubs[t]:
            for s in subs[t]:
                if p == s:
                    continue
                e = (p, s, t)
                answered = p in snap.bus_info
                if (p, t, s) in live_pairs:
                    edges.add(e)
                    live.add(e)
                elif not answered:
                    edges.add(e)          # registration only: the publisher did not answer getBusInfo
    return Graph(nodes, [], edges, live, snap.types)


def namespace_of(name):
    """'/ptrz/pan_position_controller/command' -> '/ptrz/pan_position_controller'; '/gazebo' -> '/'."""
    head = name.rstrip("/").rsplit("/", 1)[0]
    return head or "/"


def _ancestors(ns):
    parts = [p for p in ns.split("/") if p]
    return ["/" + "/".join(parts[:i]) for i in range(1, len(parts) + 1)]


def _quote(text):
    return '"%s"' % text.replace("\\", "\\\\").replace('"', '\\"')


def _ident(prefix, name):
    return _quote(prefix + name)


def to_dot(graph, opts, title="rosgraph"):
    """graphviz DOT text: nodes as ellipses, topics as boxes (rqt_graph's look), left to right;
    with ``group_namespaces`` every namespace is a labelled cluster, nested, and names inside
    it are shown relative to it (the full name is the tooltip). Edges the nodes' bus info did
    not confirm (no live connection) are dashed."""
    lines = ["digraph %s {" % _quote(title),
             '  graph [rankdir=LR, fontname="Helvetica", fontsize=11, ranksep=0.4, nodesep=0.25];',
             '  node [fontname="Helvetica", fontsize=10];',
             '  edge [fontname="Helvetica", fontsize=8, color="#444444"];']
    members = {}

    def label(name):
        ns = namespace_of(name)
        return name[len(ns) + 1:] if opts.group_namespaces and ns != "/" else name

    for n in graph.nodes:
        members.setdefault(namespace_of(n), []).append(
            "%s [label=%s, shape=ellipse, style=filled, fillcolor=\"#dbe8ff\", tooltip=%s];"
            % (_ident("n:", n), _quote(label(n)), _quote(n)))
    for t in graph.topics:
        tip = "%s [%s]" % (t, graph.types.get(t, "?"))
        members.setdefault(namespace_of(t), []).append(
            "%s [label=%s, shape=box, style=filled, fillcolor=\"#fff4d6\", tooltip=%s];"
            % (_ident("t:", t), _quote(label(t)), _quote(tip)))
    if opts.group_namespaces:
        namespaces = set()
        for ns in members:
            namespaces.update(_ancestors(ns))
        children = {}
        for ns in namespaces:
            children.setdefault(namespace_of(ns), []).append(ns)

        def emit(ns, indent):
            pad = "  " * indent
            out = ["%ssubgraph %s {" % (pad, _quote("cluster_" + ns)),
                   '%s  label=%s; style="rounded,filled"; fillcolor="#f3f3f3"; color="#999999";'
                   % (pad, _quote(ns))]
            out += [pad + "  " + m for m in members.get(ns, [])]
            for child in sorted(children.get(ns, [])):
                out += emit(child, indent + 1)
            out.append(pad + "}")
            return out

        lines += ["  " + m for m in members.get("/", [])]
        for top in sorted(children.get("/", [])):
            lines += emit(top, 1)
    else:
        for ns in sorted(members):
            lines += ["  " + m for m in members[ns]]
    topic_set = set(graph.topics)
    for src, dst, label in graph.edges:
        a = _ident("t:" if src in topic_set else "n:", src)
        b = _ident("t:" if dst in topic_set else "n:", dst)
        attrs = []
        if label:
            attrs.append("label=%s" % _quote(label))
        if (src, dst, label) not in graph.live:
            attrs.append("style=dashed")
        lines.append("  %s -> %s%s;" % (a, b, " [%s]" % ", ".join(attrs) if attrs else ""))
    lines.append("}")
    return "\n".join(lines) + "\n"


def parse_dot_edges(dot):
    """(source, target) names of the edges in DOT text ``to_dot`` wrote (for tests and tools)."""
    pat = re.compile(r'^\s*"[nt]:([^"]+)" -> "[nt]:([^"]+)"', re.M)
    return set(pat.findall(dot))
