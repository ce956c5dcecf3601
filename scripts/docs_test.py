#!/usr/bin/env python3
"""The docs test: every shell and Python block of README.md and docs/*.md runs as written, or is
marked as not run with the reason. The convention is in docs/development.md ("Code blocks in the
docs"); in short, on the line directly before a fenced ```bash / ```python block:

    <!-- docs-test: skip (reason a reader understands) -->
    <!-- docs-test: run [session=NAME] [until=CHECK,..] [expect=REGEX] [creates=PATH,..]
                        [status=N] [timeout=S] [allow=REGEX] -->

    docs_test.py                    check every block's marker, then run the blocks marked run
    docs_test.py --check            only check the markers (no ROS, a second)
    docs_test.py docs/ptrz.md       one document; docs/ptrz.md:99 only the session of that block
    docs_test.py --list             the sessions that would run
    docs_test.py --jobs 2           two sessions side by side (default: one at a time)
"""
import argparse
import glob
import hashlib
import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# fence languages that are run; every other language is text for the reader (xml, yaml, text ...)
RUNNABLE = {"bash": "bash", "sh": "bash", "shell": "bash", "python": "python", "python3": "python"}
# a block in another language whose first line starts with one of these is a command in disguise
COMMANDS = {"rosrun", "roslaunch", "rostopic", "rosservice", "rosparam", "rosbag", "rosnode", "roscore",
            "make", "source", "python3", "catkin_make", "colcon", "bash", "export", "rviz", "cd"}
# what a successful run must not print (roslaunch's and rospy's red lines, tracebacks)
RED_LINES = [re.compile(p) for p in (
    r"\[(ERROR|FATAL)\]", r"^ERROR: ", r"Traceback \(most recent call last\)", r"process has died",
    r"\[rospack\] Error", r"^Error: ", r"Segmentation fault", r"core dumped")]
OPTIONS = {"session", "until", "expect", "creates", "status", "timeout", "allow", "display"}
MARKER = re.compile(r"^\s*<!--\s*docs-test:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(```+|~~~+)\s*([^`\s]*)[^`]*$")
LIST_ITEM = re.compile(r"^(\s*)([-*+]|\d+[.)])(\s+)\S")
DEFAULT_TIMEOUT = 120.0  # wall seconds: generous, a shared 2-core machine can be slow
STOP_GRACE = 20.0  # wall seconds for a Ctrl-C'd launch to end before SIGTERM
# Sessions side by side (--jobs): a session keeps about one core busy (Python processes starting one
# after the other, a launch coming up), so two at once could use both of 2 cores; on the shared
# machine (load 13-18) two were no faster (405 s against 389 s) and a 12-command block at
# real-time factor 1 ran past its 120 s. One at a time unless asked.
JOBS = 1
# A block's process starts with Ctrl-C (SIGINT) doing what it does in a reader's shell. A test run
# started as a background job (CI scripts, nohup ... &) inherits SIGINT ignored, and an ignored
# signal stays ignored across exec: the block would then outlive the Ctrl-C. (coreutils' env, not
# a preexec_fn: sessions start processes from several threads.)
CTRL_C_ENDS = ["env", "--default-signal=INT"]
INTERRUPTED = threading.Event()  # the docs test itself got Ctrl-C: sessions stop what they run


# a line of a shell block that moves the reader's shell elsewhere (not inside a subshell)
CHANGES_DIR = re.compile(r"^\s*(cd|roscd|pushd)(\s|$)")


class Block(object):
    def __init__(self, doc, line, lang, text, marker, indent):
        self.doc, self.line, self.lang, self.text = doc, line, lang, text
        self.marker, self.indent = marker, indent  # marker: None or the comment's inside
        self.kind = RUNNABLE.get(lang)
        self.action = None  # "run" | "skip"
        self.reason = ""
        self.opts = {}

    @property
    def where(self):
        return "%s:%d" % (self.doc, self.line)


class Problem(Exception):
    pass


def parse_marker(block):
    """Fill block.action/reason/opts from its marker; raise Problem on a malformed one."""
    text = block.marker
    if text.startswith("skip"):
        m = re.match(r"^skip\s*\((.+)\)$", text)
        if not m or not m.group(1).strip():
            raise Problem("the skip marker needs a reason: <!-- docs-test: skip (needs a display) -->")
        block.action, block.reason = "skip", m.group(1).strip()
        return
    if text != "run" and not text.startswith("run "):
        raise Problem("unknown docs-test marker %r: 'run [options]' or 'skip (reason)'" % text)
    block.action = "run"
    try:
        words = shlex.split(text[3:])
    except ValueError as e:
        raise Problem("marker options do not parse (%s): quote values with spaces" % e)
    for word in words:
        key, eq, value = word.partition("=")
        if not eq or key not in OPTIONS:
            raise Problem("marker option %r: expected one of %s as key=value"
                          % (word, ", ".join(sorted(OPTIONS))))
        block.opts[key] = value
    for check in split_list(block.opts.get("until", "")):
        kind, _, name = check.partition(":")
        if kind not in ("topic", "service", "file") or not name:
            raise Problem("until=%s: each check is topic:/name, service:/name or file:path" % check)
    if block.opts.get("display", "xvfb") != "xvfb":
        raise Problem("display=%s: the only display is display=xvfb (a private X server)"
                      % block.opts["display"])
    for key in ("status", "timeout"):
        if key in block.opts:
            try:
                float(block.opts[key])
            except ValueError:
                raise Problem("%s=%s is not a number" % (key, block.opts[key]))
    for key in ("expect", "allow"):
        if key in block.opts:
            try:
                re.compile(block.opts[key])
            except re.error as e:
                raise Problem("%s=%r is not a regular expression: %s" % (key, block.opts[key], e))


def indent_of(line):
    return len(line) - len(line.lstrip(" "))


def selected(block, lines):
    """Whether a command line's doc:LINE names this block (its marker, fence or body)."""
    return None in lines or any(block.line - 1 <= n <= block.end for n in lines)


def split_list(value):
    return [v for v in value.split(",") if v]


def scan(doc, text):
    """(blocks, problems) of one Markdown text: fenced blocks with their markers, and every
    indented code block, unmarked runnable block, block without a language or bad marker."""
    lines = text.split("\n")
    blocks, problems = [], []
    i, prev_blank, list_indent = 0, True, None
    while i < len(lines):
        line = lines[i]
        fence = FENCE.match(line)
        if fence and len(fence.group(1)) < 4 + (list_indent or 0):
            indent, ticks, lang = len(fence.group(1)), fence.group(2), fence.group(3).lower()
            j = i + 1
            while j < len(lines) and not lines[j].strip().startswith(ticks[0] * len(ticks)):
                j += 1
            body = [x[indent:] if x[:indent].strip() == "" else x.lstrip() for x in lines[i + 1:j]]
            prev = MARKER.match(lines[i - 1]) if i > 0 else None
            block = Block(doc, i + 1, lang, "\n".join(body) + "\n", prev.group(1) if prev else None, indent)
            block.end = j + 1
            blocks.append(block)
            i, prev_blank = j + 1, False
            continue
        if not line.strip():
            prev_blank = True
            i += 1
            continue
        indent = indent_of(line)
        base = list_indent or 0
        if prev_blank and indent >= base + 4:
            problems.append((doc, i + 1, "an indented code block: make it a fenced block with a language "
                             "(```bash, ```python, ```text ...) and a docs-test marker if it runs"))
            while i < len(lines) and (not lines[i].strip() or indent_of(lines[i]) >= base + 4):
                i += 1
            prev_blank = True
            continue
        item = LIST_ITEM.match(line)
        if item:
            list_indent = len(item.group(1)) + len(item.group(2)) + min(len(item.group(3)), 4)
        elif prev_blank and indent < base:
            list_indent = None
        prev_blank = False
        i += 1
    for block in blocks:
        where = (block.doc, block.line)
        if not block.lang:
            problems.append(where + ("a fenced block without a language: say what it is (```bash, ```python, "
                                     "```text for output, ```xml ...)",))
            continue
        if block.marker is not None:
            try:
                parse_marker(block)
            except Problem as e:
                problems.append(where + (str(e),))
                continue
        if block.kind is None:
            first = block.text.strip().split("\n")[0].split()
            if block.action == "run":
                problems.append(where + ("a run marker on a ```%s block: only bash and python blocks run"
                                         % block.lang,))
            elif first and first[0].lstrip("$") in COMMANDS and block.marker is None:
                problems.append(where + ("a ```%s block that starts with the command '%s': make it ```bash "
                                         "(and mark it run or skip)" % (block.lang, first[0]),))
            continue
        moves = [x.split()[0] for x in block.text.split("\n") if CHANGES_DIR.match(x)]
        if block.kind == "bash" and moves:
            problems.append(where + ("a block that changes the directory ('%s'): a reader pasting the blocks "
                                     "in order in one shell is then elsewhere for the next block's relative "
                                     "paths; use rospack find, or a subshell: (cd DIR && ...)" % moves[0],))
        if block.action is None:
            problems.append(where + ("a ```%s block neither run nor marked: put <!-- docs-test: run ... --> "
                                     "or <!-- docs-test: skip (reason) --> on the line before it "
                                     "(docs/development.md)"
                                     % block.lang,))
    return blocks, problems


def documents():
    docs = glob.glob(os.path.join(ROOT, "docs", "*.md"))
    return ["README.md"] + sorted(os.path.relpath(p, ROOT) for p in docs)


def sessions(blocks):
    """Run-marked blocks grouped into sessions, in document order: blocks of one document with the
    same session=NAME share one master and run one after the other; every other block is alone."""
    out, named = [], {}
    for block in blocks:
        if block.action != "run":
            continue
        name = block.opts.get("session")
        if name is None:
            out.append([block])
        elif (block.doc, name) in named:
            named[(block.doc, name)].append(block)
        else:
            named[(block.doc, name)] = [block]
            out.append(named[(block.doc, name)])
    return out


def cost(group):
    """A session's expected run time, for starting the longest first when sessions run side by
    side: its commands (each a process that starts Python or ROS), a launch or make counting five."""
    total = 0
    for block in group:
        if block.kind == "python":
            total += 3
            continue
        previous = ""
        for line in block.text.split("\n"):
            line, continued = line.strip(), previous.endswith("\\")
            previous = line
            if not line or line.startswith("#") or continued:
                continue
            total += 5 if line.split()[0] in ("roslaunch", "make") else 1
    return total


# ---------------------------------------------------------------- running


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def made_since(path, since):
    """Whether ``path`` (relative to the workspace) exists and was written at or after wall time
    ``since``: a file left by an earlier run does not count as made by this one. (File times come
    from the kernel's coarse clock, up to a tick behind time.time(): hence the 50 ms.)"""
    try:
        return os.stat(os.path.join(ROOT, path)).st_mtime >= since - 0.05
    except OSError:
        return False


def tracked_state():
    """{path: digest} of the tracked files that differ from git's index, to see what a block rewrote."""
    # --no-optional-locks: sessions side by side run this at once; git diff would otherwise take
    # the index lock to refresh it, and one of them would fail on it
    out = subprocess.run(["git", "--no-optional-locks", "diff", "--name-only"], cwd=ROOT,
                         capture_output=True, text=True).stdout.split()
    state = {}
    for path in out:
        full = os.path.join(ROOT, path)
        state[path] = hashlib.sha1(open(full, "rb").read()).hexdigest() if os.path.exists(full) else None
    return state


class Session(object):
    """One terminal per block (as a reader pastes them), one master for all, stopped at the end."""

    def __init__(self, blocks, workdir):
        self.blocks = blocks
        self.dir = tempfile.mkdtemp(prefix="session-", dir=workdir)
        self.env = dict(os.environ)
        for var in ("DISPLAY", "ROS_MASTER_URI", "ROS_NAMESPACE", "WAYLAND_DISPLAY"):
            self.env.pop(var, None)
        self.env["ROS_MASTER_URI"] = "http://localhost:%d" % free_port()
        self.env["ROS_HOME"] = os.path.join(self.dir, "ros_home")
        self.groups = []  # process group ids still to stop
        self.xvfb = None
        self.group_of = {}
        self.procs = []  # reaped while stopping: a zombie leader would keep its group "alive"
        self.logs = {}
        self.results = {}  # block -> (ok, message, seconds)

    def start(self, block, n):
        path = os.path.join(self.dir, "block%d.%s" % (n, "py" if block.kind == "python" else "sh"))
        with open(path, "w") as f:
            f.write(block.text)
        run = 'exec python3 "$0"' if block.kind == "python" else 'exec bash -e "$0"'
        log = os.path.join(self.dir, "block%d.log" % n)
        self.logs[block] = log
        env = dict(self.env, DISPLAY=self.display()) if "display" in block.opts else self.env
        with open(log, "w") as out:
            proc = subprocess.Popen(CTRL_C_ENDS + ["bash", "-c", "source scripts/env.sh && " + run, path],
                                    cwd=ROOT, env=env,
                                    stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT,
                                    start_new_session=True)
        self.groups.append(proc.pid)
        self.group_of[proc.pid] = block
        self.procs.append(proc)
        return proc

    def display(self):
        """A private Xvfb for the blocks marked display=xvfb (started once per session). Xvfb picks
        a free display number itself (-displayfd) and says it once it accepts clients, so sessions
        side by side never race for one. -noreset: by default an X server resets when its last
        client leaves, and a GUI of the next block connecting during that reset fails at start."""
        if self.xvfb is None:
            read, write = os.pipe()
            proc = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "1280x1024x24",
                                     "-nolisten", "tcp", "-noreset"], pass_fds=(write,),
                                    stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL, start_new_session=True)
            os.close(write)
            with os.fdopen(read) as f:
                number = f.readline().strip()  # "" when Xvfb could not start
            self.xvfb = (":%s" % number, proc)
        return self.xvfb[0]

    def run_block(self, block, n):
        start, self.started = time.monotonic(), time.time()
        timeout = float(block.opts.get("timeout", DEFAULT_TIMEOUT))
        before = tracked_state()
        proc = self.start(block, n)
        checks = split_list(block.opts.get("until", ""))
        if checks:
            problem = self.wait_checks(proc, checks, start + timeout)
        else:
            status = wait_exit(proc, start + timeout)
            if status is None:
                problem = ("did not finish within %.0f s: a launch in the foreground? Give the marker "
                           "until=..., "
                           "end the line with & and wait for it, or mark the block skip" % timeout)
            else:
                want = int(float(block.opts.get("status", 0)))
                problem = None if status == want else "exit status %d (expected %d)" % (status, want)
        if problem is None:
            problem = self.check_files(block)
        rewritten = sorted(p for p, d in tracked_state().items() if before.get(p) != d)
        if problem is None and rewritten:
            problem = ("rewrote tracked files: %s (write under out/ or a path the reader gives; with --jobs "
                       "above 1 it may be a block of a session beside it)" % ", ".join(rewritten))
        self.results[block] = [problem is None, problem, time.monotonic() - start]
        return problem is None

    def wait_checks(self, proc, checks, end):
        names = [c.partition(":")[2] for c in checks if not c.startswith("file:")]
        files = [c.partition(":")[2] for c in checks if c.startswith("file:")]
        waiter = None
        if names:
            script = ('source scripts/env.sh && exec rosrun modrob_sim wait_for --timeout %.0f "$@"'
                      % max(1.0, end - time.monotonic()))
            waiter = subprocess.Popen(["bash", "-c", script, "wait_for"] + names, cwd=ROOT, env=self.env,
                                      stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                      start_new_session=True)
        while True:
            status = proc.poll()
            if status is not None:
                if waiter:
                    os.killpg(waiter.pid, signal.SIGKILL)
                    waiter.wait()
                return "ended (exit status %d) before %s" % (status, ", ".join(checks))
            names_ok = waiter is None or waiter.poll() == 0
            if waiter is not None and waiter.poll() not in (None, 0):
                return "%s (%s)" % (", ".join(checks), waiter.stdout.read().strip())
            missing = [f for f in files if not made_since(f, self.started)]
            if names_ok and not missing:
                return None
            if time.monotonic() > end or INTERRUPTED.is_set():
                if waiter:
                    os.killpg(waiter.pid, signal.SIGKILL)
                    waiter.wait()
                return "not within %.0f s: %s" % (float(end - time.monotonic()), ", ".join(missing or names))
            time.sleep(0.1)

    def check_files(self, block):
        missing = [f for f in split_list(block.opts.get("creates", "")) if not made_since(f, self.started)]
        return "did not create %s (or left an older one as it was)" % ", ".join(missing) if missing else None

    def stop(self):
        """Ctrl-C every block's process group (launches end as a reader's would), then insist.
        Returns the groups that needed more than Ctrl-C."""
        stubborn = []
        for sig, grace in ((signal.SIGINT, STOP_GRACE), (signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
            alive = self.alive()
            if not alive:
                break
            if sig != signal.SIGINT:
                stubborn += [g for g in alive if g not in stubborn]
            for g in alive:
                try:
                    os.killpg(g, sig)
                except ProcessLookupError:
                    pass
            end = time.monotonic() + grace
            while time.monotonic() < end and self.alive():
                time.sleep(0.1)
        if self.xvfb is not None:
            self.xvfb[1].terminate()
            self.xvfb[1].wait()
        return stubborn

    def alive(self):
        for proc in self.procs:
            proc.poll()
        return [g for g in self.groups if group_alive(g)]

    def red_lines(self):
        for block, log in self.logs.items():
            allow = re.compile(block.opts["allow"]) if "allow" in block.opts else None
            with open(log, errors="replace") as f:
                text = f.read()
            bad = [x for x in strip_ansi(text).split("\n")
                   if any(p.search(x) for p in RED_LINES) and not (allow and allow.search(x))]
            result = self.results.get(block)
            if result is None:
                continue
            if result[0] and bad:
                result[0], result[1] = False, "a successful run printed %d red line(s):\n  %s" % (
                    len(bad), "\n  ".join(bad[:8]))
            expect = block.opts.get("expect")
            if result[0] and expect is not None and not re.search(expect, strip_ansi(text), re.M):
                result[0], result[1] = False, "the output has no match for expect=%r" % block.opts["expect"]


def wait_exit(proc, end):
    """proc's exit status, or None when wall time ``end`` passed (or the docs test was interrupted)."""
    while not INTERRUPTED.is_set():
        try:
            return proc.wait(timeout=max(0.0, min(0.2, end - time.monotonic())))
        except subprocess.TimeoutExpired:
            if time.monotonic() >= end:
                return None
    return None


def group_alive(pgid):
    try:
        os.killpg(pgid, 0)
        return True
    except ProcessLookupError:
        return False
    except PermissionError:
        return True


def strip_ansi(text):
    return re.sub(r"\x1b\[[0-9;]*[A-Za-z]|\x1b\][^\x07]*\x07", "", text)


def run_session(blocks, workdir):
    session = Session(blocks, workdir)
    try:
        for n, block in enumerate(blocks, 1):
            if INTERRUPTED.is_set() or not session.run_block(block, n):
                break
    finally:
        t = time.monotonic()
        stubborn = session.stop()
        session.stop_seconds = time.monotonic() - t
    for pgid in stubborn:
        result = session.results.get(session.group_of[pgid])
        if result and result[0]:
            result[0] = False
            result[1] = "its processes did not end within %.0f s of Ctrl-C (SIGINT)" % STOP_GRACE
    session.red_lines()
    for block in blocks:
        if block.action == "run" and block not in session.results:
            session.results[block] = [False, "not run: an earlier block of its session failed", 0.0]
    return session


def run_groups(groups, workdir, jobs, report):
    """Run the sessions ``groups``, ``jobs`` side by side, the longest (by :func:`cost`) first so
    that the last to end is a short one; ``report(i, group, session, seconds)`` gets each ended
    session (``i`` its place in ``groups``, from 1), one call at a time. True when Ctrl-C
    interrupted the run (the sessions that ran are stopped then)."""
    queue = sorted(enumerate(groups, 1), key=lambda item: -cost(item[1]))
    lock = threading.Lock()

    def worker():
        while not INTERRUPTED.is_set():
            with lock:
                if not queue:
                    return
                i, group = queue.pop(0)
            start = time.monotonic()
            session = run_session(group, workdir)
            with lock:
                report(i, group, session, time.monotonic() - start)

    workers = [threading.Thread(target=worker) for _ in range(max(1, min(jobs, len(queue))))]
    try:
        for thread in workers:
            thread.start()
        for thread in workers:
            while thread.is_alive():
                thread.join(0.2)
    except KeyboardInterrupt:
        INTERRUPTED.set()
        print("[docs] interrupted: stopping the sessions that run", flush=True)
        for thread in workers:
            thread.join()
    return INTERRUPTED.is_set()


def write_junit(path, cases):
    """cases: (classname, name, seconds, failure message or None)."""
    suite = ET.Element("testsuite", name="docs", tests=str(len(cases)),
                       failures=str(sum(1 for c in cases if c[3])), errors="0", skipped="0")
    for classname, name, seconds, failure in cases:
        case = ET.SubElement(suite, "testcase", classname=classname, name=name, time="%.1f" % seconds)
        if failure:
            ET.SubElement(case, "failure", message=failure.split("\n")[0]).text = failure
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="unicode")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("targets", nargs="*", help="README.md, docs/x.md or docs/x.md:LINE (default: all)")
    ap.add_argument("--check", action="store_true", help="only check that every block is run or marked")
    ap.add_argument("--list", action="store_true", help="print the sessions and exit")
    ap.add_argument("--junit", help="write JUnit XML here")
    ap.add_argument("--keep", action="store_true", help="keep the blocks' scripts and logs (printed)")
    ap.add_argument("--workdir", metavar="DIR",
                    help="make the folder of the blocks' scripts and logs in DIR (default: $TMPDIR); it is "
                         "removed after a run that passed, kept (and printed) after one that failed")
    ap.add_argument("--jobs", type=int, default=JOBS, metavar="N",
                    help="sessions run side by side (default %d; each has its own master and Xvfb)" % JOBS)
    args = ap.parse_args()

    wanted = {}
    for t in args.targets:
        doc, _, line = t.partition(":")
        wanted.setdefault(os.path.relpath(os.path.abspath(doc), ROOT), set()).add(int(line) if line else None)
    cases, blocks = [], []
    n_problems = 0
    for doc in documents():
        if wanted and doc not in wanted:
            continue
        found, problems = scan(doc, open(os.path.join(ROOT, doc)).read())
        blocks += found
        for d, line, message in problems:
            print("[docs] %s:%d: %s" % (d, line, message))
            cases.append(("docs." + d, "L%d markers" % line, 0.0, message))
        n_problems += len(problems)
    runnable = [b for b in blocks if b.kind]
    skipped = [b for b in runnable if b.action == "skip"]
    groups = sessions(blocks)
    if wanted:
        groups = [g for g in groups if any(selected(b, wanted[b.doc]) for b in g)]
    print("[docs] %d shell/python blocks in %d documents: %d to run in %d sessions, %d marked not run, "
          "%d problems" % (len(runnable), len({b.doc for b in blocks}), sum(len(g) for g in groups),
                           len(groups), len(skipped), n_problems), flush=True)
    if args.list:
        for g in groups:
            print("  " + " + ".join(b.where for b in g))
        return 1 if n_problems else 0
    if args.check:
        if args.junit:
            write_junit(args.junit, cases or [("docs", "markers", 0.0, None)])
        return 1 if n_problems else 0

    if args.workdir:
        os.makedirs(args.workdir, exist_ok=True)
    workdir = tempfile.mkdtemp(prefix="modrob-docs-test-", dir=args.workdir)
    failed = 0
    done = []

    def report(i, group, session, seconds):
        """One session's lines, printed together (sessions end in any order; called under a lock)."""
        nonlocal failed
        lines = []
        for block in group:
            ok, message, block_seconds = session.results[block]
            cases.append(("docs." + block.doc, "L%d" % block.line, block_seconds, None if ok else message))
            if not ok:
                failed += 1
                lines.append("[docs] %s FAILED: %s\n       log: %s"
                             % (block.where, message, session.logs.get(block, "-")))
                if block in session.logs:
                    with open(session.logs[block], errors="replace") as f:
                        tail = strip_ansi(f.read()).rstrip().split("\n")[-25:]
                    lines.append("       | " + "\n       | ".join(tail))
        done.append(i)
        lines.append("[docs] [%d/%d, #%d] %s: %s in %.0f s (%s; stop %.1f s)" % (
            len(done), len(groups), i, " + ".join(b.where for b in group),
            "ok" if all(session.results[b][0] for b in group) else "FAILED", seconds,
            " + ".join("%.1f" % session.results[b][2] for b in group), session.stop_seconds))
        print("\n".join(lines), flush=True)

    started = time.monotonic()
    interrupted = run_groups(groups, workdir, args.jobs, report)
    if args.junit and not interrupted:
        write_junit(args.junit, cases)
    if args.keep or failed:
        print("[docs] scripts and logs: %s" % workdir)
    else:
        shutil.rmtree(workdir, ignore_errors=True)
    if interrupted:
        return 130
    print("[docs] %d blocks run, %d failed, %d marked not run; %d marker problems; %.0f s, %d side by side"
          % (sum(len(g) for g in groups), failed, len(skipped), n_problems, time.monotonic() - started,
             max(1, args.jobs)))
    return 1 if failed or n_problems else 0


if __name__ == "__main__":
    sys.exit(main())
