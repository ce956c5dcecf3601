"""The spawner's shutdown (cli.take_down): it stops and unloads its controllers, and it ends
promptly and quietly when the simulator is going down at the same time, also when the simulator
accepts the request's connection and never answers (seen at the end of ptrz.launch: roslaunch had
to SIGKILL the spawner)."""
import socket
import threading
import time
import types

import pytest
import rospy

from modrob_sim.ros_control import cli


class Client(object):
    """A ManagerClient whose requests go to ``address`` as rospy's do: connect, wait for the answer
    (a socket timeout there is rospy's ServiceException)."""
    names = {"switch_controller": "/ptrz/controller_manager/switch_controller",
             "unload_controller": "/ptrz/controller_manager/unload_controller"}

    def __init__(self, address=None):
        self.address = address
        self.calls = []

    def _request(self, what):
        self.calls.append(what)
        if self.address is None:
            return types.SimpleNamespace(ok=True)
        s = socket.socket()
        try:
            s.connect(self.address)
            s.recv(1)
        except socket.timeout as e:
            raise rospy.ServiceException("unable to connect to service: %s" % e)
        finally:
            s.close()

    def switch_controller(self, start, stop, strictness, start_asap, timeout):
        return self._request(("switch", tuple(stop)))

    def unload_controller(self, name):
        return self._request(("unload", name))


@pytest.fixture
def said(monkeypatch):
    lines = []
    monkeypatch.setattr(rospy, "loginfo", lambda m, *a: lines.append(("info", m % a if a else m)))
    monkeypatch.setattr(rospy, "logwarn", lambda m, *a: lines.append(("warn", m % a if a else m)))
    monkeypatch.setattr(rospy, "wait_for_service", lambda name, timeout=None: None)
    monkeypatch.setattr(cli, "SHUTDOWN_REQUEST_TIMEOUT", 0.5)
    monkeypatch.setattr(cli, "GONE_WAIT", 1.0)
    return lines


@pytest.fixture
def deaf_server():
    """A listening socket that never accepts: connections queue in its backlog, nothing answers."""
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    s.listen(5)
    yield s.getsockname()
    s.close()


def run(client, registered, limit=10.0):
    """take_down in a thread; the wall seconds it took (fails if it has not ended within ``limit``)."""
    t0 = time.monotonic()
    thread = threading.Thread(target=cli.take_down, args=(client, ["jsc", "pan"], 30.0, registered),
                              daemon=True)
    thread.start()
    thread.join(limit)
    assert not thread.is_alive(), "take_down hangs on a simulator that does not answer"
    return time.monotonic() - t0


def test_it_stops_and_unloads_its_controllers_in_reverse(said):
    client = Client()
    run(client, lambda name: True)
    assert client.calls == [("switch", ("jsc", "pan")), ("unload", "pan"), ("unload", "jsc")]
    assert ("info", "Unloaded pan") in said and not [m for k, m in said if k == "warn"]
    assert socket.getdefaulttimeout() is None


def test_a_simulator_already_gone_is_not_asked(said):
    client = Client()
    run(client, lambda name: False)
    assert client.calls == []
    assert "no longer offered" in said[-1][1]


def test_a_simulator_that_never_answers_and_leaves_ends_it_quietly(said, deaf_server):
    gone_at = time.monotonic() + 0.8      # it leaves the master while the request waits

    seconds = run(Client(deaf_server), lambda name: time.monotonic() < gone_at)
    assert seconds < 3.0
    assert said[-1] == ("info", "Controller Spawner: the controller_manager went away with the simulator, "
                                "and its controllers with it")
    assert socket.getdefaulttimeout() is None


def test_a_simulator_that_never_answers_and_stays_is_named_in_a_warning(said, deaf_server):
    seconds = run(Client(deaf_server), lambda name: True)
    assert seconds < 4.0
    assert said[-1][0] == "warn" and "couldn't reach controller_manager" in said[-1][1]
