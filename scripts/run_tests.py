#!/usr/bin/env python3
"""Run the workspace's tests and print one combined closing line ``N passed, N failed``.

Tier 1: pytest over every package's ``test/unit/`` and ``scripts/test/`` (pure libraries; tests
that need a master start their own on a free port). Tier 2: every package's ``test/*.test``
through ``rostest``, each on its own free master port so that runs cannot collide, and the docs
test (``scripts/docs_test.py``: the code blocks of README.md and docs/*.md), two at a time.

    run_tests.py                   both tiers
    run_tests.py --tier 1          unit tests only
    run_tests.py -k sim            only packages / .test files whose path contains 'sim'
    run_tests.py --tier 2 -k docs  only the docs test
    run_tests.py --tier 2 -j 1     rostests one after another
"""
import argparse
import concurrent.futures
import glob
import os
import socket
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# One results folder per run (several runs may go on at once on a shared machine).
RESULTS = os.path.join(ROOT, "out", "test-results", time.strftime("%Y%m%d-%H%M%S-") + str(os.getpid()))


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


def run_unit(pattern):
    # every package's test/unit, and the workspace scripts' own tests (scripts/test)
    candidates = (glob.glob(os.path.join(ROOT, "src", "*", "test", "unit"))
                  + [os.path.join(ROOT, "scripts", "test")])
    # -k matches the path inside the workspace (not the folder the workspace is in)
    dirs = sorted(d for d in candidates
                  if pattern in os.path.relpath(d, ROOT) and glob.glob(os.path.join(d, "test_*.py")))
    if not dirs:
        print("[tests] tier 1: no unit test directories matched")
        return 0, 0, 0, 0
    xml = os.path.join(RESULTS, "unit.xml")
    cmd = [sys.executable, "-m", "pytest", "-q", "--import-mode=importlib", "-p", "no:cacheprovider",
           "--junitxml", xml, "-o", "junit_family=xunit2"] + dirs
    print("[tests] tier 1: pytest over %d packages" % len(dirs), flush=True)
    if os.path.exists(xml):
        os.remove(xml)
    rc = subprocess.call(cmd, cwd=ROOT)
    passed, failed, skipped, xfailed = junit_counts(xml)
    if rc not in (0, 5) and failed == 0:
        failed = 1  # pytest itself failed (collection or usage error): count it
        print("[tests] pytest exited with %d" % rc)
    return passed, failed, skipped, xfailed


def rostest_files(pattern):
    # -k matches the path inside the workspace (not the folder the workspace is in)
    return sorted(f for f in glob.glob(os.path.join(ROOT, "src", "*", "test", "*.test"))
                  if pattern in os.path.relpath(f, ROOT))


def run_rostest(path, timeout):
    """One .test file through rostest on its own master: (passed, failed, skipped, logfile, seconds)."""
    pkg = os.path.basename(os.path.dirname(os.path.dirname(path)))
    name = os.path.splitext(os.path.basename(path))[0]
    outdir = os.path.join(RESULTS, "rostest", pkg, name)     # its own: files may run at once
    os.makedirs(outdir, exist_ok=True)
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % free_port(),
               ROS_HOME=os.path.join(RESULTS, "ros_home"))
    logfile = os.path.join(RESULTS, "rostest", pkg, name + ".log")
    start = time.time()
    # rostest starts its master on a free port of its own (port 0); ROS_MASTER_URI is set to
    # an unused port as well so that nothing can fall back to a master of the user's.
    cmd = ["rostest", "--results-base-dir", outdir, path]
    with open(logfile, "w") as log:
        try:
            rc = subprocess.call(cmd, cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT,
                                 timeout=timeout)
        except subprocess.TimeoutExpired:
            rc = "timeout after %d s" % timeout
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
    return p, f, s, rc, logfile, time.time() - start


def run_docs(timeout):
    """The docs test (scripts/docs_test.py): every shell and Python block of README.md and docs/*.md
    is run or marked as not run. (passed, failed, 0, rc, logfile, seconds)"""
    xml = os.path.join(RESULTS, "docs.xml")
    logfile = os.path.join(RESULTS, "docs.log")
    start = time.time()
    with open(logfile, "w") as log:
        try:
            cmd = [sys.executable, os.path.join(ROOT, "scripts", "docs_test.py"), "--junit", xml]
            rc = subprocess.call(cmd, cwd=ROOT, stdout=log, stderr=subprocess.STDOUT, timeout=timeout)
        except subprocess.TimeoutExpired:
            rc = "timeout after %d s" % timeout
    passed, failed, _, _ = junit_counts(xml)
    if rc != 0 and failed == 0:
        failed = 1
    return passed, failed, 0, rc, logfile, time.time() - start


def run_tier2(pattern, timeout, jobs):
    """Every matching .test file and (with no pattern or one in its path) the docs test, ``jobs``
    at a time: most of a rostest's wall time is a master, nodes starting and simulated time
    passing, so two share this 2-core machine well. The docs test, the longest, starts first."""
    work = [("docs", None)] if pattern in "scripts/docs_test.py" else []
    work += [("%s/%s" % (os.path.basename(os.path.dirname(os.path.dirname(f))),
                         os.path.splitext(os.path.basename(f))[0]), f) for f in rostest_files(pattern)]
    total = [0, 0, 0, 0]
    if not work:
        print("[tests] tier 2: no .test files matched")
        return tuple(total)
    print("[tests] tier 2: %d rostest files%s, %d at a time"
          % (len(work) - (work[0][0] == "docs"), " and the docs' code blocks (scripts/docs_test.py)"
             if work[0][0] == "docs" else "", jobs), flush=True)
    failures = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        running = {pool.submit(run_docs if path is None else run_rostest,
                               *((timeout,) if path is None else (path, timeout))): label
                   for label, path in work}
        for i, done in enumerate(concurrent.futures.as_completed(running), 1):
            label = running[done]
            p, f, s, rc, logfile, seconds = done.result()
            total[0] += p
            total[1] += f
            total[2] += s
            status = "ok" if f == 0 else "FAILED (rc=%s, log: %s)" % (rc, os.path.relpath(logfile, ROOT))
            print("[tests] [%d/%d] %s: %d passed, %d failed in %.0f s  %s"
                  % (i, len(work), label, p, f, seconds, status), flush=True)
            if f:
                failures.append(logfile)
    for logfile in failures:
        print("---- last lines of %s" % os.path.relpath(logfile, ROOT))
        with open(logfile, errors="replace") as fh:
            if logfile.endswith("docs.log"):
                print("".join(line for line in fh if not line.startswith("       |"))[-6000:])
            else:
                print("".join(fh.readlines()[-40:]))
    return tuple(total)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tier", type=int, choices=(1, 2), help="run only this tier")
    ap.add_argument("-k", dest="pattern", default="", help="only paths containing this string")
    ap.add_argument("--timeout", type=int, default=900, help="seconds per rostest file (default 900)")
    ap.add_argument("-j", "--jobs", type=int, default=int(os.environ.get("MODROB_TEST_JOBS", "2")),
                    help="tier 2 files run at once (default 2, or $MODROB_TEST_JOBS)")
    args = ap.parse_args()
    os.makedirs(RESULTS, exist_ok=True)
    print("[tests] results and logs: %s" % os.path.relpath(RESULTS, ROOT))
    totals = [0, 0, 0, 0]
    parts = []
    if args.tier in (None, 1):
        parts.append(run_unit(args.pattern))
    if args.tier in (None, 2):
        parts.append(run_tier2(args.pattern, args.timeout, max(1, args.jobs)))
    for part in parts:
        for i, v in enumerate(part):
            totals[i] += v
    passed, failed, skipped, xfailed = totals
    line = "%d passed, %d failed" % (passed, failed)
    if xfailed:
        line += ", %d xfailed (known limits that fail as expected)" % xfailed
    if skipped:
        line += ", %d skipped" % skipped
    print(line)
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
