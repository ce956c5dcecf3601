"""Tier 1: the node graph's pure core on a fixed snapshot (no master)."""
import pytest

from rqt_graph.graph_model import Options, SystemSnapshot, build_graph, namespace_of, parse_dot_edges, to_dot

PUBS = {"/clock": ["/gazebo"], "/ptrz/joint_states": ["/gazebo"], "/ptrz/pan/state": ["/gazebo"],
        "/ptrz/pan/command": ["/ptrz/teleop"], "/tf": ["/rsp"], "/rosout": ["/gazebo", "/rsp"],
        "/rosout_agg": ["/rosout"], "/ptrz/pan/pid/parameter_updates": ["/gazebo"]}
SUBS = {"/clock": ["/rsp", "/ptrz/teleop"], "/ptrz/joint_states": ["/rsp"], "/ptrz/pan/command": ["/gazebo"],
        "/ptrz/tilt/command": ["/gazebo"], "/rosout": ["/rosout"]}
BUS = {"/gazebo": [("/clock", "/rsp"), ("/ptrz/joint_states", "/rsp")],
       "/ptrz/teleop": [("/ptrz/pan/command", "/gazebo")], "/rsp": []}


def snap(bus=BUS):
    return SystemSnapshot(PUBS, SUBS, {"/clock": "rosgraph_msgs/Clock"}, bus)


def test_nodes_topics_edges_and_debug_hidden():
    g = build_graph(snap(), Options())
    assert g.nodes == ["/gazebo", "/ptrz/teleop", "/rsp"]
    assert "/rosout" not in g.topics and "/ptrz/tilt/command" in g.topics
    assert g.has_edge("/ptrz/teleop", "/ptrz/pan/command") and g.has_edge("/ptrz/pan/command", "/gazebo")
    assert not g.has_edge("/gazebo", "/ptrz/pan/command")
    assert ("/gazebo", "/clock", "") in g.live and ("/clock", "/rsp", "") in g.live
    assert ("/gazebo", "/ptrz/pan/state", "") not in g.live        # nobody listens
    shown = build_graph(snap(), Options(hide_debug=False))
    assert "/rosout" in shown.nodes and "/rosout_agg" in shown.topics


@pytest.mark.parametrize("opts,gone,kept", [
    (Options(hide_dead_sinks=True), "/ptrz/tilt/command", "/ptrz/pan/command"),
    (Options(hide_leaf_topics=True), "/ptrz/pan/state", "/ptrz/joint_states"),
    (Options(hide_tf=True), "/tf", "/clock"),
    (Options(hide_params=True), "/ptrz/pan/pid/parameter_updates", "/ptrz/pan/state"),
    (Options(filter="ptrz -tilt"), "/ptrz/tilt/command", "/ptrz/pan/command"),
])
def test_filters(opts, gone, kept):
    g = build_graph(snap(), opts)
    assert gone not in g.topics and kept in g.topics


def test_nodes_mode_prefers_live_connections_and_falls_back_to_registrations():
    g = build_graph(snap(), Options(mode="nodes"))
    assert ("/ptrz/teleop", "/gazebo", "/ptrz/pan/command") in g.live
    assert ("/gazebo", "/rsp", "/ptrz/joint_states") in g.edges
    assert not any(e[0] == e[1] for e in g.edges)
    # /gazebo publishes /clock to /ptrz/teleop by registration, but its bus info has no such connection
    assert ("/gazebo", "/ptrz/teleop", "/clock") not in g.edges
    no_bus = build_graph(snap(bus={}), Options(mode="nodes"))
    assert ("/gazebo", "/ptrz/teleop", "/clock") in no_bus.edges and not no_bus.live


def test_dot_groups_namespaces_and_dashes_unconfirmed_edges():
    opts = Options(group_namespaces=True)
    dot = to_dot(build_graph(snap(), opts), opts)
    assert 'subgraph "cluster_/ptrz" {' in dot and 'subgraph "cluster_/ptrz/pan" {' in dot
    assert '"n:/ptrz/teleop" [label="teleop"' in dot
    assert '"n:/gazebo" -> "t:/ptrz/pan/state" [style=dashed];' in dot
    assert '"n:/gazebo" -> "t:/clock";' in dot
    edges = parse_dot_edges(dot)
    assert ("/ptrz/teleop", "/ptrz/pan/command") in edges
    flat = to_dot(build_graph(snap(), Options()), Options())
    assert "cluster_" not in flat and '"n:/ptrz/teleop" [label="/ptrz/teleop"' in flat


def test_namespace_of_and_bad_mode():
    assert namespace_of("/ptrz/pan/command") == "/ptrz/pan" and namespace_of("/gazebo") == "/"
    with pytest.raises(ValueError, match="mode 'graph' is not one of nodes_topics, nodes"):
        Options(mode="graph")
