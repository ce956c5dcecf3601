#!/usr/bin/env python3
"""Run the workspace's tests and print one combined closing line ``N passed, N failed``.

Tier 1: pytest over every package's ``test/unit/`` and ``scripts/test/`` (pure libraries; tests
that need a master start their own on a free port), one pytest per package. Tier 2: every
package's ``test/*.test`` through ``rostest``, each on its own free master port so that runs
cannot collide, and the docs test (``scripts/docs_test.py``: the code blocks of README.md and
docs/*.md). Those jobs run two at a time, the longest kinds first; each writes its own log and
JUnit XML under out/test-results/<run>/, and a failing job's log ends the output.

Each job runs with TMPDIR set to a fresh empty directory of its own (a short path under the system's
temporary directory): a test removes what it creates there. Whatever a job leaves in it, other than
ALLOWED_LEFTOVERS, fails that job with the names listed; the directories are removed when the job
ends, and the run's directory when the run ends, whether tests failed or the run was stopped:
Ctrl-C (SIGINT), SIGTERM (what CI and `timeout` send to cancel a job) and SIGHUP (the terminal
closed) interrupt the running jobs
(each runs in a process group of its own, so its whole tree gets the SIGINT a terminal would send),
kill what is left of them after JobProcesses.GRACE_S, remove the directories and exit with 128 + the
signal's number. A run that could not clean up (SIGKILL) leaves its directory with its pid in it:
the next run removes it once that process is gone.

    run_tests.py                   both tiers
    run_tests.py --tier 1          unit tests only
    run_tests.py -k sim            only packages / .test files whose path contains 'sim'
    run_tests.py --tier 2 -k docs  only the docs test
    run_tests.py -j 1              one job after another
"""
import argparse
import concurrent.futures
import fnmatch
import glob
import os
import re
import shutil
import signal
import socket
import stat
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# One results folder per run (several runs may go on at once on a shared machine).
RESULTS = os.path.join(ROOT, "out", "test-results", time.strftime("%Y%m%d-%H%M%S-") + str(os.getpid()))
# ROS_HOME of every job (ROS logs, rostest outputs under test_output/): with the run's results, not ~/.ros
ROS_HOME = os.path.join(RESULTS, "ros_home")


# What third-party code leaves in a job's TMPDIR that the test cannot remove, and why (names as
# fnmatch patterns). Anything else left there fails the job.
ALLOWED_LEFTOVERS = {
    # Qt (RViz, rqt, the camera renderer) makes $TMPDIR/runtime-<user> when XDG_RUNTIME_DIR is not
    # set, as on a CI machine without a login session; one per user, reused.
    "runtime-*": "Qt's runtime directory",
}


class TempDirs:
    """The run's temporary directory: one fresh TMPDIR per job inside it. Kept short, as the paths
    of unix sockets made in TMPDIR (Ray's) are limited to 107 bytes: in /tmp when the system's
    temporary directory has a longer path than LONGEST_BASE."""
    LONGEST_BASE = 40
    PREFIX = "modrob-test-"
    OWNER = "pid"          # in the run's directory: the runner's pid, for the stale-directory check

    def __init__(self):
        base = tempfile.gettempdir()
        if len(base) > self.LONGEST_BASE and os.path.isdir("/tmp"):
            print("[tests] TMPDIR %s is too long for the sockets tests make in it: using /tmp" % base)
            base = "/tmp"
        stale = self.remove_stale(base)
        if stale:
            print("[tests] removed %d temporary director%s of earlier runs that ended without cleaning up "
                  "(killed; their process is gone): %s" % (len(stale), "y" if len(stale) == 1 else "ies",
                                                           ", ".join(stale)), flush=True)
        self.root = tempfile.mkdtemp(prefix=self.PREFIX, dir=base)
        with open(os.path.join(self.root, self.OWNER + ".new"), "w") as fh:
            fh.write("%d\n" % os.getpid())
        os.rename(os.path.join(self.root, self.OWNER + ".new"), os.path.join(self.root, self.OWNER))
        self.count = 0

    @classmethod
    def remove_stale(cls, base):
        """Remove the run directories in ``base`` whose runner is gone (killed with SIGKILL, which
        cannot be handled); the paths removed. Only directories of this user named PREFIX* with an
        OWNER file naming a pid that no process has: a live runner's, another user's, one without an
        OWNER file (a run starting, or not ours) or anything else is never touched."""
        removed = []
        for name in sorted(os.listdir(base)):
            path = os.path.join(base, name)
            if not name.startswith(cls.PREFIX):
                continue
            try:
                st = os.lstat(path)
                if not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid():
                    continue
                with open(os.path.join(path, cls.OWNER)) as fh:
                    pid = int(fh.read().strip())
            except (OSError, ValueError):
                continue
            if pid <= 0 or process_exists(pid):
                continue
            shutil.rmtree(path, ignore_errors=True)
            removed.append(path)
        return removed

    def new(self):
        """A fresh empty TMPDIR for one job, and a scratch directory beside it for what the runner
        itself puts there (pytest's --basetemp)."""
        self.count += 1
        tmpdir = os.path.join(self.root, str(self.count))
        os.mkdir(tmpdir)
        os.mkdir(tmpdir + "-runner")
        return tmpdir, tmpdir + "-runner"

    @staticmethod
    def finish(tmpdir):
        """Remove a job's directories; the sorted names the job left in its TMPDIR that are not
        ALLOWED_LEFTOVERS."""
        try:
            left = sorted(name for name in os.listdir(tmpdir)
                          if not any(fnmatch.fnmatch(name, allowed) for allowed in ALLOWED_LEFTOVERS))
        except FileNotFoundError:
            left = []
        for path in (tmpdir, tmpdir + "-runner"):
            shutil.rmtree(path, ignore_errors=True)
        return left

    def close(self):
        """Remove the run's directory; the names still in it (a job's directory whose job never
        ended, or one a process left running recreated after its job ended)."""
        try:
            left = sorted(name for name in os.listdir(self.root) if name != self.OWNER)
        except FileNotFoundError:
            left = []
        shutil.rmtree(self.root, ignore_errors=True)
        return left


def process_exists(pid):
    """Whether a process ``pid`` exists (a zombie counts: it is not reaped yet)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:      # another user's
        return True
    return True


class Stopped(Exception):
    """The run was told to stop (one of STOP_SIGNALS): raised in the main thread by the handler."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


class JobProcesses:
    """The commands the jobs run, each in a process group of its own with stdin from /dev/null (a
    background group must not read the terminal). A terminal's Ctrl-C reaches only the runner's
    group and SIGTERM only the runner, so the runner stops the jobs itself: SIGINT to each job's
    group (pytest then runs its teardowns, rostest's roslaunch stops its nodes), SIGKILL to the group
    after GRACE_S (roslaunch gives a node 15 s for SIGINT, then SIGTERM)."""
    GRACE_S = 20.0

    def __init__(self):
        self.lock = threading.RLock()     # the second-signal handler may run while the main thread holds it
        self.running = set()
        self.stopping = False

    def call(self, cmd, timeout, **kw):
        """Run ``cmd`` to its end: its exit status, or a reason when it timed out or the run was
        stopped before it started. A timed-out command is stopped as a stopped run's are."""
        with self.lock:
            if self.stopping:
                return "not started: the run was stopped"
            proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, process_group=0, **kw)
            self.running.add(proc)
        try:
            try:
                return proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.signal(proc, signal.SIGINT)
                try:
                    proc.wait(timeout=self.GRACE_S)
                except subprocess.TimeoutExpired:
                    self.signal(proc, signal.SIGKILL)
                    proc.wait()
                return "timeout after %d s" % timeout
        finally:
            with self.lock:
                self.running.discard(proc)

    @staticmethod
    def signal(proc, signum):
        try:
            os.killpg(proc.pid, signum)
        except ProcessLookupError:     # the group is gone already
            pass

    def stop_all(self, signum):
        """Send ``signum`` to every running job's group; no job starts after this."""
        with self.lock:
            self.stopping = True
            for proc in self.running:
                self.signal(proc, signum)


PROCS = JobProcesses()


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def junit_counts(path):
    """(passed, failed, skipped, xfailed) from a JUnit XML file written by pytest or rostest.
    An expected failure (pytest's xfail, a known limit the test documents) is its own count, not
    a skip: it ran and failed as it should."""
    if not os.path.exists(path):
        return 0, 0, 0, 0
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError:
        return 0, 1, 0, 0
    suites = [root] if root.tag == "testsuite" else root.findall("testsuite")
    passed = failed = skipped = xfailed = 0
    for suite in suites:
        tests = int(suite.get("tests", 0))
        bad = int(suite.get("failures", 0)) + int(suite.get("errors", 0))
        skip = int(suite.get("skipped", suite.get("skip", 0)) or 0)
        xfail = sum(1 for case in suite.iter("testcase")
                    if any(s.get("type") == "pytest.xfail" for s in case.findall("skipped")))
        # a class whose setUpClass fails is reported as tests=0, errors=1: never count below 0
        passed += max(0, tests - bad - skip)
        failed += bad
        skipped += max(0, skip - xfail)
        xfailed += xfail
    return passed, failed, skipped, xfailed


def unit_jobs(pattern):
    """One pytest job per package's test/unit (and scripts/test) whose path contains ``pattern``."""
    candidates = (glob.glob(os.path.join(ROOT, "src", "*", "test", "unit"))
                  + [os.path.join(ROOT, "scripts", "test")])
    # -k matches the path inside the workspace (not the folder the workspace is in)
    dirs = sorted(d for d in candidates
                  if pattern in os.path.relpath(d, ROOT) and glob.glob(os.path.join(d, "test_*.py")))
    return [("unit " + os.path.relpath(d, ROOT).replace(os.sep + "test" + os.sep + "unit", "")
             .replace("src" + os.sep, ""), run_unit, d) for d in dirs]


def run_unit(path, timeout, tmpdir, scratch):
    """pytest over one test directory: (passed, failed, skipped, xfailed, rc, logfile, seconds)."""
    name = os.path.relpath(path, ROOT).replace(os.sep, "_")
    xml = os.path.join(RESULTS, "unit", name + ".xml")
    logfile = os.path.join(RESULTS, "unit", name + ".log")
    os.makedirs(os.path.dirname(xml), exist_ok=True)
    # tmp_path goes to the runner's scratch directory: without --basetemp pytest keeps the last
    # three sessions' directories in $TMPDIR/pytest-of-<user>.
    cmd = [sys.executable, "-m", "pytest", "-q", "-rfE", "--import-mode=importlib", "-p", "no:cacheprovider",
           "--basetemp", os.path.join(scratch, "pytest"), "--junitxml", xml, "-o", "junit_family=xunit2",
           path]
    start = time.time()
    with open(logfile, "w") as log:
        rc = PROCS.call(cmd, timeout, cwd=ROOT, env=dict(os.environ, TMPDIR=tmpdir, ROS_HOME=ROS_HOME),
                        stdout=log, stderr=subprocess.STDOUT)
    passed, failed, skipped, xfailed = junit_counts(xml)
    if rc not in (0, 5) and failed == 0:
        failed = 1  # pytest itself failed (collection or usage error, timeout): count it
    return passed, failed, skipped, xfailed, rc, logfile, time.time() - start


def rostest_jobs(pattern):
    # -k matches the path inside the workspace (not the folder the workspace is in)
    files = sorted(f for f in glob.glob(os.path.join(ROOT, "src", "*", "test", "*.test"))
                   if pattern in os.path.relpath(f, ROOT))
    return [("%s/%s" % (os.path.basename(os.path.dirname(os.path.dirname(f))),
                        os.path.splitext(os.path.basename(f))[0]), run_rostest, f) for f in files]


XFAIL = re.compile(r"<!--\s*run_tests:\s*xfail\s*\((.+?)\)\s*-->", re.S)


def known_failure(path):
    """The reason of a .test file's ``<!-- run_tests: xfail (reason) -->`` marker, else None: a known
    failure that is counted as xfailed while it fails, and as a failure once it passes (then the
    marker must go)."""
    with open(path) as fh:
        m = XFAIL.search(fh.read())
    return " ".join(m.group(1).split()) if m else None


def run_rostest(path, timeout, tmpdir, _scratch):
    """One .test file through rostest on its own master."""
    pkg = os.path.basename(os.path.dirname(os.path.dirname(path)))
    name = os.path.splitext(os.path.basename(path))[0]
    outdir = os.path.join(RESULTS, "rostest", pkg, name)     # its own: files may run at once
    os.makedirs(outdir, exist_ok=True)
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % free_port(),
               ROS_HOME=ROS_HOME, TMPDIR=tmpdir)
    logfile = os.path.join(RESULTS, "rostest", pkg, name + ".log")
    start = time.time()
    # rostest starts its master on a free port of its own (port 0); ROS_MASTER_URI is set to
    # an unused port as well so that nothing can fall back to a master of the user's.
    cmd = ["rostest", "--results-base-dir", outdir, path]
    with open(logfile, "w") as log:
        rc = PROCS.call(cmd, timeout, cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT)
    results = glob.glob(os.path.join(outdir, "**", "*.xml"), recursive=True)
    # rosunit-*.xml hold the test cases of each test node; rostest-*.xml is a summary with
    # one entry per node (it fails a node that crashed before writing its own results).
    p = f = s = 0
    for x in results:
        if os.path.basename(x).startswith("rosunit-"):
            a, b, c, _ = junit_counts(x)
            p, f, s = p + a, f + b, s + c
    f = max(f, sum(junit_counts(x)[1] for x in results if os.path.basename(x).startswith("rostest-")))
    if rc != 0 and f == 0:
        f = 1
    if p + f == 0:
        f = 1  # a .test that ran no test is a failure
    reason = known_failure(path)
    if reason is not None:
        if f:
            return p, 0, s, f, "known failure: %s" % reason, logfile, time.time() - start
        return p, 1, s, 0, "passed, yet marked as a known failure: remove its run_tests xfail marker", \
            logfile, time.time() - start
    return p, f, s, 0, rc, logfile, time.time() - start


def docs_jobs(pattern):
    """The docs test runs with `-k docs` or with no pattern (its sessions one at a time: the
    jobs beside it keep the other core busy)."""
    return [("docs", run_docs, None)] if pattern in "scripts/docs_test.py" else []


def run_docs(_path, timeout, tmpdir, _scratch):
    """The docs test (scripts/docs_test.py): every shell and Python block of README.md and docs/*.md
    is run or marked as not run."""
    xml = os.path.join(RESULTS, "docs.xml")
    logfile = os.path.join(RESULTS, "docs.log")
    start = time.time()
    with open(logfile, "w") as log:
        # the blocks' scripts and logs beside the docs test's own (kept only when it fails)
        cmd = [sys.executable, os.path.join(ROOT, "scripts", "docs_test.py"), "--junit", xml,
               "--workdir", RESULTS]
        rc = PROCS.call(cmd, timeout, cwd=ROOT, env=dict(os.environ, TMPDIR=tmpdir), stdout=log,
                        stderr=subprocess.STDOUT)
    passed, failed, _, _ = junit_counts(xml)
    if rc != 0 and failed == 0:
        failed = 1
    return passed, failed, 0, 0, rc, logfile, time.time() - start


def failure_lines(logfile):
    """The end of a failed job's log: pytest's and the docs test's summaries come last."""
    with open(logfile, errors="replace") as fh:
        lines = [line for line in fh if not line.startswith("       |")]   # docs test: block echo
    return "".join(lines[-60:])


def run_in_tmpdir(temp, fn, path, timeout):
    """One job with a fresh TMPDIR of its own; what it left there (not ALLOWED_LEFTOVERS) is one
    more failure, named at the end of its log."""
    tmpdir, scratch = temp.new()
    try:
        p, f, s, x, rc, logfile, seconds = fn(path, timeout, tmpdir, scratch)
    finally:
        left = temp.finish(tmpdir)
    if left:
        with open(logfile, "a") as log:
            log.write("\n[tests] this job left in its TMPDIR: %s\n" % ", ".join(left))
    return p, f + bool(left), s, x, rc, logfile, seconds, left


def run_jobs(jobs, workers, timeout, temp):
    """Run (label, function, path) jobs ``workers`` at a time, a line each as they end; totals."""
    total = [0, 0, 0, 0]
    failures = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        running = {pool.submit(run_in_tmpdir, temp, fn, path, timeout): label for label, fn, path in jobs}
        try:
            for i, done in enumerate(concurrent.futures.as_completed(running), 1):
                label = running[done]
                p, f, s, x, rc, logfile, seconds, left = done.result()
                for k, v in enumerate((p, f, s, x)):
                    total[k] += v
                status = "ok" if f == 0 else "FAILED (rc=%s, log: %s)" % (rc, os.path.relpath(logfile, ROOT))
                if f == 0 and x and isinstance(rc, str):
                    status = "ok (%s; log: %s)" % (rc, os.path.relpath(logfile, ROOT))
                if left:
                    status += ("\n[tests]   left in TMPDIR: %s -- the test must remove what it creates "
                               "(tempfile.TemporaryDirectory, pytest's tmp_path; a .test's output files "
                               "under ROS_HOME)" % ", ".join(left))
                print("[tests] [%d/%d] %s: %d passed, %d failed%s in %.0f s  %s"
                      % (i, len(jobs), label, p, f, ", %d xfailed" % x if x else "", seconds, status),
                      flush=True)
                if f:
                    failures.append(logfile)
        except Stopped:
            # the jobs not started yet are dropped; the running ones are interrupted, killed if they
            # do not end within the grace time (at once on a second signal), and leaving the pool
            # waits for them and their clean-up
            for future in running:
                future.cancel()
            for signum in STOP_SIGNALS:
                signal.signal(signum, lambda *_: PROCS.stop_all(signal.SIGKILL))
            PROCS.stop_all(signal.SIGINT)
            if concurrent.futures.wait(running, timeout=PROCS.GRACE_S).not_done:
                PROCS.stop_all(signal.SIGKILL)
            raise
    for logfile in failures:
        print("---- last lines of %s" % os.path.relpath(logfile, ROOT))
        print(failure_lines(logfile))
    return total


#: what stops a run: Ctrl-C, SIGTERM (CI, `timeout`) and SIGHUP (the terminal closed: the jobs run in
#: process groups of their own, so without it they would run on without the runner)
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def stop_run(signum, _frame):
    raise Stopped(signum)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tier", type=int, choices=(1, 2), help="run only this tier")
    ap.add_argument("-k", dest="pattern", default="", help="only paths containing this string")
    ap.add_argument("--timeout", type=int, default=900, help="seconds per job (default 900)")
    ap.add_argument("-j", "--jobs", type=int, default=int(os.environ.get("MODROB_TEST_JOBS", "2")),
                    help="jobs at once (default 2, or $MODROB_TEST_JOBS)")
    args = ap.parse_args()
    os.makedirs(RESULTS, exist_ok=True)
    print("[tests] results and logs: %s" % os.path.relpath(RESULTS, ROOT))
    # the long kinds first (a package's unit tests, the docs test), so the two workers end together
    jobs = []
    if args.tier in (None, 1):
        jobs += unit_jobs(args.pattern)
    if args.tier in (None, 2):
        jobs += docs_jobs(args.pattern) + rostest_jobs(args.pattern)
    if not jobs:
        print("[tests] nothing matched -k %r" % args.pattern)
        return 1
    kinds = sum(1 for j in jobs if j[1] is run_unit), sum(1 for j in jobs if j[1] is run_rostest)
    print("[tests] %d unit test packages, %d rostest files%s; %d at a time"
          % (kinds[0], kinds[1], ", the docs test" if any(j[1] is run_docs for j in jobs) else "",
             max(1, args.jobs)), flush=True)
    temp = TempDirs()
    stopped = []
    for signum in STOP_SIGNALS:
        signal.signal(signum, stop_run)
    try:
        passed, failed, skipped, xfailed = run_jobs(jobs, max(1, args.jobs), args.timeout, temp)
    except Stopped as exc:
        stopped.append(exc.signum)
    finally:
        # a signal from here on only marks the run as stopped: the clean-up goes on
        for signum in STOP_SIGNALS:
            signal.signal(signum, lambda signum, _frame: stopped.append(signum))
        stray = temp.close()
        if stray:
            print("[tests] still in %s at the end (removed): %s -- a job that never ended, or a process "
                  "a test left running" % (temp.root, ", ".join(stray)), flush=True)
    if stopped:
        print("[tests] %s by %s: the running jobs were stopped and %s removed"
              % ("interrupted" if stopped[0] == signal.SIGINT else "terminated",
                 signal.Signals(stopped[0]).name, temp.root), flush=True)
        return 128 + stopped[0]
    if stray:
        failed += 1
    line = "%d passed, %d failed" % (passed, failed)
    if xfailed:
        line += ", %d xfailed (known limits that fail as expected)" % xfailed
    if skipped:
        line += ", %d skipped" % skipped
    print(line)
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
