"""modrob_sim.scenario_launch: a runner's launch ends with the runner, whatever ends the runner
(stand-in launches: Python children, no ROS needed)."""
import os
import signal
import socket
import subprocess
import sys
import textwrap
import time

from modrob_sim import scenario_launch

SLEEPER = (sys.executable, "-c", "import time; time.sleep(60)")
# a "launch" that starts a child of its own, says both pids and ignores SIGINT when asked to
FAMILY = textwrap.dedent("""
    import signal, subprocess, sys, time
    if "--deaf" in sys.argv:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    child = subprocess.Popen([sys.executable, "-c", "import signal, sys, time; "
                              "sys.argv[1] == 'deaf' and signal.signal(signal.SIGINT, signal.SIG_IGN); "
                              "print(flush=True); time.sleep(60)",
                              "deaf" if "--deaf-child" in sys.argv else "-"], stdout=subprocess.PIPE)
    child.stdout.readline()     # its SIGINT handler is set
    print(child.pid, flush=True)
    time.sleep(60)
""")


def alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    with open("/proc/%d/stat" % pid) as fh:       # a zombie is gone too
        return fh.read().split(") ")[-1][0] != "Z"


def wait_gone(pid, timeout=10.0):
    end = time.monotonic() + timeout
    while alive(pid) and time.monotonic() < end:
        time.sleep(0.02)
    return not alive(pid)


def test_free_port_can_be_bound():
    port = scenario_launch.free_port()
    with socket.socket() as s:
        s.bind(("127.0.0.1", port))


def test_start_runs_on_its_own_master_port_in_its_own_group(tmp_path, monkeypatch):
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:11311")
    with open(tmp_path / "log", "w") as log:
        proc = scenario_launch.start(["pkg", "x.launch"], log, port=12345,
                                     program=(sys.executable, "-c", "import sys; print(sys.argv[1:])"))
    proc.wait(10)
    assert os.environ["ROS_MASTER_URI"] == "http://127.0.0.1:12345"
    assert (tmp_path / "log").read_text().strip() == "['-p', '12345', 'pkg', 'x.launch']"


def test_stop_ends_the_whole_group_and_escalates_when_sigint_is_ignored(monkeypatch):
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:11311")     # start() sets it
    ignored = signal.signal(signal.SIGINT, signal.SIG_IGN)   # as a runner started with `&` has it
    try:
        for args, grace in (([], 10.0), (["--deaf"], 0.3)):
            proc = scenario_launch.start(args, subprocess.PIPE, program=(sys.executable, "-c", FAMILY))
            child = int(proc.stdout.readline())
            start = time.monotonic()
            status = scenario_launch.stop(proc, grace=grace)
            proc.stdout.close()
            assert status == (-signal.SIGKILL if args else -signal.SIGINT)
            assert time.monotonic() - start < grace + 5.0
            assert wait_gone(child), "the launch's child %d outlived it" % child
    finally:
        signal.signal(signal.SIGINT, ignored)


def test_stop_ends_a_child_that_outlives_its_leader(monkeypatch):
    # a renderer whose restarted child ignores Ctrl-C: the leader ends, the child must too
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:11311")
    proc = scenario_launch.start(["--deaf-child"], subprocess.PIPE, program=(sys.executable, "-c", FAMILY))
    child = int(proc.stdout.readline())
    assert scenario_launch.stop(proc, grace=10.0) == -signal.SIGINT
    proc.stdout.close()
    assert wait_gone(child), "the deaf child %d outlived its leader" % child


def test_stop_of_a_process_that_leads_no_group_signals_only_it():
    # in this test's own group (stop() must not signal that), SIGINT at its default, and ready
    proc = subprocess.Popen(list(scenario_launch.CTRL_C_ENDS) + [
        sys.executable, "-c", "import time; print(flush=True); time.sleep(60)"], stdout=subprocess.PIPE)
    proc.stdout.readline()
    assert scenario_launch.stop(proc, grace=10.0) == -signal.SIGINT
    proc.stdout.close()


def test_a_runner_ended_by_sigterm_ends_its_launch(tmp_path):
    runner = textwrap.dedent("""
        import sys, time
        from modrob_sim import scenario_launch
        scenario_launch.sigterm_as_exit()
        launch = scenario_launch.start([], open(sys.argv[1], "w"), program=%r)
        try:
            print(launch.pid, flush=True)   # inside the try: the test's SIGTERM may come at once
            time.sleep(60)
        finally:
            scenario_launch.stop(launch, grace=5.0)
    """ % (SLEEPER,))
    proc = subprocess.Popen([sys.executable, "-c", runner, str(tmp_path / "log")], stdout=subprocess.PIPE)
    launch = int(proc.stdout.readline())
    assert alive(launch)
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(10) == 128 + signal.SIGTERM
    assert wait_gone(launch), "the launch %d outlived its runner" % launch
    proc.stdout.close()
