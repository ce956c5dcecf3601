"""A two-node Ray cluster on this machine, started as on two hosts: the head (`ray start --head`)
in this network namespace, a worker node (`ray start --address=<head>`) in a network namespace of
its own (veth pair, its own address) with its own host name (UTS namespace). `sweep --address`
runs four slide trials on it and the table names both hosts. Needs root (ip netns, unshare)."""
import os
import random
import signal
import socket
import subprocess
import sys
import time
import uuid

import pytest

pd = pytest.importorskip("pandas")

HERE = os.path.dirname(os.path.abspath(__file__))
SWEEP = os.path.join(os.path.dirname(os.path.dirname(HERE)), "scripts", "sweep")
NODE_B = "sweep-node-b"


def sh(*cmd):
    return subprocess.run(list(cmd), capture_output=True, text=True)


def namespaces_available():
    if os.geteuid() != 0:
        return "needs root for ip netns and unshare"
    name = "swpchk%d" % os.getpid()
    if sh("ip", "netns", "add", name).returncode != 0:
        return "ip netns add does not work here"
    sh("ip", "netns", "del", name)
    return ""


@pytest.fixture
def two_nodes(tmp_path):
    why = namespaces_available()
    if why:
        pytest.skip(why)
    tag = uuid.uuid4().hex[:5]
    ns, veth_a, veth_b = "swp%s" % tag, "swa%s" % tag, "swb%s" % tag
    net = random.randint(1, 250)
    head_ip, node_ip = "10.231.%d.1" % net, "10.231.%d.2" % net
    port = 6300 + random.randint(0, 600)
    setup = [["ip", "netns", "add", ns],
             ["ip", "link", "add", veth_a, "type", "veth", "peer", "name", veth_b],
             ["ip", "link", "set", veth_b, "netns", ns],
             ["ip", "addr", "add", head_ip + "/24", "dev", veth_a],
             ["ip", "link", "set", veth_a, "up"],
             ["ip", "netns", "exec", ns, "ip", "addr", "add", node_ip + "/24", "dev", veth_b],
             ["ip", "netns", "exec", ns, "ip", "link", "set", veth_b, "up"],
             ["ip", "netns", "exec", ns, "ip", "link", "set", "lo", "up"]]
    from modrob_sweep import runner
    temp_dir = runner.new_ray_temp_dir()    # both nodes' sessions, as in one cluster on one machine
    # RAY_raylet_start_wait_time_s: a node's raylet has 10 s to register by default, too few for the
    # second node on a loaded 2-core machine
    env = dict(os.environ, RAY_AUTH_MODE="token", RAY_kill_child_processes_on_worker_exit="0",
               RAY_raylet_start_wait_time_s="120", MODROB_SWEEP_TEST_CLUSTER=tag)
    procs = []
    try:
        for cmd in setup:
            r = sh(*cmd)
            assert r.returncode == 0, "%s: %s" % (" ".join(cmd), r.stderr)
        head_log = open(tmp_path / "head.log", "w")
        head = ["ray", "start", "--head", "--node-ip-address", head_ip, "--port", str(port),
                "--num-cpus", "1", "--include-dashboard=false", "--temp-dir", temp_dir, "--block"]
        procs.append(subprocess.Popen(head, env=env, stdout=head_log, stderr=subprocess.STDOUT,
                                      start_new_session=True))
        wait_for_line(tmp_path / "head.log", "Ray runtime started", procs[0])
        node_log = open(tmp_path / "node.log", "w")
        procs.append(subprocess.Popen(
            ["ip", "netns", "exec", ns, "unshare", "--uts", "sh", "-c",
             "hostname %s && exec ray start --address=%s:%d --node-ip-address=%s --num-cpus=1 --temp-dir=%s "
             "--block" % (NODE_B, head_ip, port, node_ip, temp_dir)],
            env=env, stdout=node_log, stderr=subprocess.STDOUT, start_new_session=True))
        wait_for_line(tmp_path / "node.log", "Ray runtime started", procs[1])
        yield "%s:%d" % (head_ip, port), env
    finally:
        for p in procs:
            stop_group(p)
        sh("ip", "netns", "del", ns)
        sh("ip", "link", "del", veth_a)
        runner.shutdown()                   # removes temp_dir


def wait_for_line(path, text, proc, timeout=120.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if text in open(path).read():
            return
        assert proc.poll() is None, "ray start ended: %s" % open(path).read()[-2000:]
        time.sleep(0.2)
    raise AssertionError("no '%s' within %g s: %s" % (text, timeout, open(path).read()[-2000:]))


def stop_group(proc):
    """ray start --block and the Ray processes it started share its process group."""
    for sig, wait in ((signal.SIGTERM, 15.0), (signal.SIGKILL, 5.0)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        deadline = time.monotonic() + wait
        while time.monotonic() < deadline:
            try:
                os.killpg(proc.pid, 0)
            except ProcessLookupError:
                proc.wait()
                return
            proc.poll()
            time.sleep(0.1)


def test_a_sweep_on_two_nodes_names_both_hosts(two_nodes, tmp_path):
    address, env = two_nodes
    out = tmp_path / "results"
    proc = subprocess.run([sys.executable, SWEEP, "slide_friction", "--runs", "1", "--address", address,
                           "--out", str(out)], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "the Ray cluster at %s" % address in proc.stdout
    df = pd.read_csv(out / "trials.csv")
    assert len(df) == 4 and set(df["outcome"]) <= {"success", "failure"}
    assert set(df["host"]) == {socket.gethostname(), NODE_B}
    assert "Hosts: " in (out / "summary.md").read_text() and NODE_B in (out / "summary.md").read_text()
