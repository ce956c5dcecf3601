"""twist_mux's rules without ROS: priorities, timeouts, locks (silent heartbeat locks too), ties,
and the configuration errors."""
import pytest

from twist_mux.mux import ConfigError, TwistMux, parse_entries

TOPICS = [{"name": "joy", "topic": "joy_teleop/cmd_vel", "timeout": 0.5, "priority": 10},
          {"name": "kb", "topic": "kb_teleop/cmd_vel", "timeout": 0.5, "priority": 9},
          {"name": "external", "topic": "cmd_vel", "timeout": 0.5, "priority": 1}]
LOCKS = [{"name": "e_stop", "topic": "e_stop", "timeout": 0.0, "priority": 255},
         {"name": "pause", "topic": "pause", "timeout": 0.0, "priority": 9}]


def mux(topics=TOPICS, locks=LOCKS):
    return TwistMux(parse_entries(topics, "~topics"), parse_entries(locks, "~locks"))


def test_the_higher_priority_wins_while_fresh_then_the_lower_comes_back():
    m = mux()
    assert m.on_twist("external", "ext", 0.0) == "ext"
    assert m.on_twist("joy", "joy", 0.1) == "joy"
    assert m.on_twist("external", "ext", 0.2) is None          # masked by the fresh joystick
    assert m.on_twist("external", "ext", 0.55) is None         # joy is 0.45 s old: still fresh
    assert m.on_twist("external", "ext", 0.65) == "ext"        # joy 0.55 s old: stale


def test_a_lock_masks_inputs_below_its_priority_only():
    m2 = mux()
    m2.on_lock("pause", True, 0.0)
    assert m2.on_twist("external", "ext", 0.1) is None
    assert m2.on_twist("joy", "joy", 0.2) == "joy"
    m2.on_lock("pause", False, 0.3)
    assert m2.on_twist("external", "ext", 1.0) == "ext"
    m2.on_lock("e_stop", True, 1.1)
    assert m2.on_twist("joy", "joy", 1.2) is None


def test_a_lock_at_the_inputs_priority_does_not_mask_it():
    m = mux()
    m.on_lock("pause", True, 0.0)
    assert m.lock_priority(0.0) == 9
    # as twist_mux: masked only when its priority is below the lock's; kb (9) is not
    assert m.on_twist("kb", "kb", 0.1) == "kb"


def test_a_lock_with_a_timeout_is_a_heartbeat():
    m = mux(locks=[{"name": "alive", "topic": "alive", "timeout": 0.5, "priority": 50}])
    assert m.on_twist("joy", "joy", 0.0) is None               # no heartbeat yet: locked
    m.on_lock("alive", False, 0.1)
    assert m.on_twist("joy", "joy", 0.2) == "joy"
    assert m.on_twist("joy", "joy", 0.7) is None               # heartbeat 0.6 s old


def test_timeout_zero_never_goes_stale_and_equal_priorities_take_the_first():
    m = mux(topics=[{"name": "a", "topic": "a", "timeout": 0, "priority": 5},
                    {"name": "b", "topic": "b", "timeout": 0, "priority": 5}], locks=[])
    # as twist_mux: an input with timeout 0 is never stale, even before its first message, so the
    # first of two equal priorities holds the output from the start
    assert m.on_twist("b", "b", 0.0) is None
    assert m.on_twist("a", "a", 100.0) == "a"
    assert m.on_twist("a", "a", 1e6) == "a"


def test_priority_zero_is_never_passed_on_as_in_twist_mux():
    m = mux(topics=[{"name": "z", "topic": "z", "timeout": 0.5, "priority": 0}], locks=[])
    assert m.on_twist("z", "z", 0.0) is None


def test_priorities_are_clamped_and_duplicates_warned():
    m = mux(topics=[{"name": "a", "topic": "a", "timeout": 0.5, "priority": 999},
                    {"name": "a", "topic": "b", "timeout": 0.5, "priority": 3}], locks=[])
    assert m.velocities["a"].priority == 255
    assert any("clamped" in w for w in m.warnings)
    assert any("two entries are named 'a'" in w for w in m.warnings)


def test_the_dictionary_form_is_read_too():
    got = parse_entries({"joy": {"topic": "j", "timeout": 0.5, "priority": 3}}, "~topics")
    assert got == [("joy", "j", 0.5, 3)]


@pytest.mark.parametrize("entries, words", [
    ("nope", ["~topics must be a list"]),
    ([{"name": "a", "topic": "a", "priority": 1}], ["~topics[0] (a) lacks timeout"]),
    ([{"name": "a", "topic": "a", "timeout": -1, "priority": 1}], ["~topics[0] (a): timeout", ">= 0"]),
    ([{"name": "a", "topic": "a", "timeout": 0.5, "priority": 1.5}], ["priority must be a whole number"]),
    ([{"name": "", "topic": "a", "timeout": 0.5, "priority": 1}], ["non-empty strings"]),
    ([3], ["~topics[0] must be a dictionary"]),
])
def test_bad_entries_name_the_parameter_and_entry(entries, words):
    with pytest.raises(ConfigError) as err:
        parse_entries(entries, "~topics")
    for w in words:
        assert w in str(err.value)


def test_status_says_what_is_masked_and_locked():
    m = mux()
    m.on_twist("joy", "joy", 0.0)
    m.on_lock("pause", True, 0.0)
    status = dict(m.status(0.1))
    assert status["velocity joy"] == "unmasked (listening to joy_teleop/cmd_vel @ 0.5s with priority #10)"
    assert status["velocity external"].startswith("masked")
    assert status["lock pause"].startswith("locked") and status["lock e_stop"].startswith("free")
    assert status["current priority"] == "9"
