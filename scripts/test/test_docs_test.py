"""The docs test's own tests: what counts as covered, and that a block that fails, prints a red
line, never ends, or ends too early fails it (scripts/docs_test.py)."""
import importlib.util
import os
import subprocess
import textwrap

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("docs_test", os.path.join(HERE, "..", "docs_test.py"))
docs_test = importlib.util.module_from_spec(spec)
spec.loader.exec_module(docs_test)


def scan(text):
    blocks, problems = docs_test.scan("doc.md", textwrap.dedent(text))
    return blocks, [(line, message) for _, line, message in problems]


def test_marked_blocks_are_covered_and_text_blocks_need_no_marker():
    blocks, problems = scan("""\
        Intro.

        <!-- docs-test: skip (needs a display) -->
        ```bash
        rviz
        ```

        <!-- docs-test: run session=a until=topic:/clock,file:out/x.png expect="a b" -->
        ```python
        print("a b")
        ```

        ```text
        RESULT: fine
        ```
        """)
    assert problems == []
    skip, run, text = blocks
    assert (skip.action, skip.reason, skip.line) == ("skip", "needs a display", 4)
    assert run.action == "run" and run.kind == "python" and run.opts["expect"] == "a b"
    assert run.opts["until"] == "topic:/clock,file:out/x.png" and run.text == 'print("a b")\n'
    assert text.kind is None and text.action is None


def test_uncovered_blocks_are_named_with_the_fix():
    _, problems = scan("""\
        ```bash
        roslaunch foo bar.launch
        ```

        <!-- docs-test: skip -->
        ```bash
        make demo
        ```

        <!-- docs-test: run -->

        ```python
        print(1)
        ```

        ```
        no language
        ```

        ```text
        rosrun pkg node
        ```

        <!-- docs-test: run -->
        ```xml
        <launch/>
        ```

        <!-- docs-test: run speed=2 -->
        ```bash
        true
        ```
        """)
    lines = [line for line, _ in problems]
    text = "\\n".join(message for _, message in problems)
    assert lines == [1, 6, 12, 16, 20, 25, 30]
    assert "neither run nor marked" in problems[0][1] and "docs/development.md" in problems[0][1]
    assert "needs a reason" in problems[1][1]
    assert "neither run nor marked" in problems[2][1]  # the marker must be on the line directly before
    assert "without a language" in problems[3][1]
    assert "starts with the command 'rosrun'" in problems[4][1]
    assert "only bash and python blocks run" in problems[5][1]
    assert "speed=2" in text


def test_indented_code_blocks_are_refused_but_list_continuations_are_not():
    _, problems = scan("""\
        Text:

            make demo

        - an item
          continued

          a second paragraph of the item

        1. numbered
           ```bash
           echo in a list
           ```
        """)
    assert [line for line, _ in problems] == [3, 11]
    assert "indented code block" in problems[0][1]
    assert "neither run nor marked" in problems[1][1]


def test_the_repository_docs_are_covered():
    """The fast half of the docs test: every block of README.md and docs/*.md run or marked."""
    problems = []
    for doc in docs_test.documents():
        with open(os.path.join(docs_test.ROOT, doc)) as f:
            problems += docs_test.scan(doc, f.read())[1]
    assert problems == []


def run(text, tmp_path):
    blocks, problems = docs_test.scan("doc.md", textwrap.dedent(text))
    assert problems == []
    results = {}
    for group in docs_test.sessions(blocks):
        results.update(docs_test.run_session(group, str(tmp_path)).results)
    return [results[b] for b in blocks if b.action == "run"]


def test_blocks_pass_fail_and_share_a_session(tmp_path):
    results = run("""\
        <!-- docs-test: run session=s expect="^master http://localhost:[0-9]+$" -->
        ```bash
        echo "master $ROS_MASTER_URI"
        ```

        <!-- docs-test: run session=s status=3 -->
        ```bash
        exit 3
        ```

        <!-- docs-test: run session=s -->
        ```bash
        false
        echo never
        ```

        <!-- docs-test: run session=s -->
        ```bash
        true
        ```
        """, tmp_path)
    assert [r[0] for r in results] == [True, True, False, False]
    assert "exit status 1" in results[2][1]
    assert "an earlier block of its session failed" in results[3][1]


def test_red_lines_and_missing_output_fail_a_block(tmp_path):
    results = run("""\
        <!-- docs-test: run -->
        ```bash
        echo "[ERROR] [1.0]: something broke"
        ```

        <!-- docs-test: run allow="something broke" -->
        ```bash
        echo "[ERROR] [1.0]: something broke"
        ```

        <!-- docs-test: run expect=hello -->
        ```python
        print("goodbye")
        ```
        """, tmp_path)
    assert not results[0][0] and "red line" in results[0][1] and "something broke" in results[0][1]
    assert results[1][0]
    assert not results[2][0] and "expect='hello'" in results[2][1]


def test_until_waits_for_a_file_then_stops_the_block(tmp_path):
    target = os.path.relpath(str(tmp_path / "made.txt"), docs_test.ROOT)
    results = run("""\
        <!-- docs-test: run until=file:%s timeout=20 -->
        ```bash
        touch %s
        exec tail -f /dev/null
        ```

        <!-- docs-test: run until=file:%s.never timeout=20 -->
        ```bash
        echo gone
        ```

        <!-- docs-test: run timeout=1 -->
        ```bash
        exec tail -f /dev/null
        ```
        """ % (target, target, target), tmp_path)
    assert results[0][0], results[0]
    assert not results[1][0] and "ended (exit status 0) before" in results[1][1]
    assert not results[2][0] and "did not finish within 1 s" in results[2][1]


def test_tracked_state_sees_a_rewritten_file(tmp_path, monkeypatch):
    subprocess.check_call(["git", "init", "-q", str(tmp_path)])
    (tmp_path / "a.txt").write_text("one\n")
    subprocess.check_call(["git", "-C", str(tmp_path), "add", "a.txt"])
    monkeypatch.setattr(docs_test, "ROOT", str(tmp_path))
    before = docs_test.tracked_state()
    (tmp_path / "a.txt").write_text("two\n")
    after = docs_test.tracked_state()
    assert before == {} and list(after) == ["a.txt"]


@pytest.mark.parametrize("marker", ["skip ()", "run until=clock", "run timeout=soon", "run expect=(",
                                    "run display=vnc", "later"])
def test_bad_markers_are_refused(marker):
    _, problems = scan("<!-- docs-test: %s -->\n```bash\ntrue\n```\n" % marker)
    assert len(problems) == 1


def test_sessions_side_by_side_get_displays_of_their_own(tmp_path):
    """Each session's Xvfb picks its own free display (-displayfd), also when started at once."""
    import threading
    sessions = [docs_test.Session([], str(tmp_path)) for _ in range(2)]
    threads = [threading.Thread(target=s.display) for s in sessions]
    try:
        for t in threads:
            t.start()
        for t in threads:
            t.join(30)
        displays = [s.xvfb[0] for s in sessions]
        assert len(set(displays)) == 2 and all(d != ":" for d in displays)
        for d in displays:
            assert os.path.exists("/tmp/.X11-unix/X%s" % d[1:])
    finally:
        for s in sessions:
            s.stop()


def test_a_file_left_by_an_earlier_run_is_not_made_by_the_block(tmp_path):
    old = tmp_path / "old.txt"
    old.write_text("from an earlier run\n")
    os.utime(str(old), (1e9, 1e9))
    target = os.path.relpath(str(old), docs_test.ROOT)
    results = run("""\
        <!-- docs-test: run creates=%s -->
        ```bash
        true
        ```

        <!-- docs-test: run until=file:%s timeout=3 -->
        ```bash
        exec tail -f /dev/null
        ```

        <!-- docs-test: run creates=%s -->
        ```bash
        touch %s
        ```
        """ % (target, target, target, target), tmp_path)
    assert not results[0][0] and "did not create" in results[0][1]
    assert not results[1][0] and "not within" in results[1][1]
    assert results[2][0], results[2]


def test_sessions_run_side_by_side(tmp_path):
    """Two sessions that each wait for the other's file pass only when they run at once; the one
    with more commands counts as the longer (it is started first)."""
    a, b = (os.path.relpath(str(tmp_path / name), docs_test.ROOT) for name in ("a", "b"))
    wait = "for i in $(seq 300); do [ -e %s ] && exit 0; sleep 0.1; done; exit 1"
    blocks, problems = docs_test.scan("doc.md", textwrap.dedent("""\
        <!-- docs-test: run session=one -->
        ```bash
        touch %s
        %s
        ```

        <!-- docs-test: run session=two -->
        ```bash
        touch %s
        echo two
        %s
        ```
        """) % (a, wait % b, b, wait % a))
    assert problems == []
    groups = docs_test.sessions(blocks)
    assert docs_test.cost(groups[1]) > docs_test.cost(groups[0])
    ended = []
    docs_test.run_groups(groups, str(tmp_path), 2, lambda i, group, session, seconds: ended.append(
        (i, session.results[group[0]][0])))
    assert sorted(ended) == [(1, True), (2, True)]


def test_a_block_that_leaves_the_workspace_folder_is_refused():
    """Pasted in order into one shell, a block's roscd/cd would break the next block's src/... and
    out/... paths (the docs test runs each block from the workspace folder and would not see it)."""
    _, problems = scan("""\
        <!-- docs-test: run -->
        ```bash
        source scripts/env.sh
        roscd modrob_sim
        ```

        <!-- docs-test: skip (a display) -->
        ```bash
          cd out && ls
        ```

        <!-- docs-test: run -->
        ```bash
        (cd out && ls)
        rospack find modrob_sim
        echo cd roscd
        ```
        """)
    assert [line for line, _ in problems] == [2, 8]
    assert "'roscd'" in problems[0][1] and "rospack find" in problems[0][1]
    assert "'cd'" in problems[1][1]
