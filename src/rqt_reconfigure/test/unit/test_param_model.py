"""Tier 1: the reconfigure GUI's pure core (descriptions, slider mapping, typed values, tree)."""
import math

import pytest

from rqt_reconfigure.errors import ReconfigureError
from rqt_reconfigure.param_model import (SLIDER_TICKS, format_value, group_from_dict, matches,
                                         parse_edit_method, server_tree)

PID = {"name": "Default", "type": "", "state": True, "groups": {}, "parameters": [
    {"name": "p", "type": "double", "min": -100000.0, "max": 100000.0, "default": 100.0,
     "description": "Proportional gain.", "edit_method": "", "level": 1},
    {"name": "antiwindup", "type": "bool", "min": False, "max": True, "default": False,
     "description": "", "edit_method": "", "level": 1}]}

ENUM = ("{'enum': [{'name': 'Low', 'type': 'int', 'value': 0, 'srcline': 1, 'srcfile': 'x', "
        "'description': 'slow', 'ctype': 'int', 'cconsttype': 'const int'}, "
        "{'name': 'High', 'type': 'int', 'value': 1, 'srcline': 1, 'srcfile': 'x', 'description': 'fast', "
        "'ctype': 'int', 'cconsttype': 'const int'}], 'enum_description': 'speed'}")


def test_pid_description_gives_a_slider_for_p_and_a_checkbox_for_antiwindup():
    group = group_from_dict(PID)
    p, aw = group.params
    assert p.kind == "double" and p.has_range
    assert aw.kind == "bool" and not aw.has_range


def test_slider_round_trip_hits_readable_values():
    p = group_from_dict(PID).params[0]
    assert p.tick_range() == (0, SLIDER_TICKS)
    for value in (-100000.0, 0.0, 200.0, 400.0, 100000.0):
        assert p.from_ticks(p.to_ticks(value)) == value
    assert p.to_ticks(1e9) == SLIDER_TICKS          # clamped


def test_int_slider_is_the_value_itself():
    spec = group_from_dict({"parameters": [{"name": "n", "type": "int", "min": -5, "max": 5,
                                            "default": 0}]}).params[0]
    assert spec.tick_range() == (-5, 5)
    assert spec.from_ticks(spec.to_ticks(3)) == 3


def test_infinite_or_empty_range_has_no_slider():
    spec = group_from_dict({"parameters": [{"name": "x", "type": "double", "min": -math.inf, "max": math.inf,
                                            "default": 0.0}]}).params[0]
    assert not spec.has_range


@pytest.mark.parametrize("text,message", [("abc", "'abc' is not a finite double for parameter 'p'"),
                                          ("nan", "not a finite double"),
                                          ("2e5", "outside [-100000, 100000]")])
def test_bad_typed_values_name_the_parameter(text, message):
    p = group_from_dict(PID).params[0]
    with pytest.raises(ReconfigureError, match=message.replace("[", r"\[").replace("]", r"\]")):
        p.parse(text)


def test_typed_values():
    p, aw = group_from_dict(PID).params
    assert p.parse(" 250 ") == 250.0
    assert aw.parse("true") is True and aw.parse("0") is False


def test_enum_edit_method():
    choices = parse_edit_method(ENUM, "speed")
    assert [(c.name, c.value, c.description) for c in choices] == [("Low", 0, "slow"), ("High", 1, "fast")]
    with pytest.raises(ReconfigureError, match="'speed' has an edit_method that is not a Python literal"):
        parse_edit_method("{'enum': [", "speed")


def test_nested_groups_and_unknown_types():
    d = dict(PID, groups={"g": {"name": "g", "type": "collapse", "parameters": [
        {"name": "s", "type": "str", "default": "a"}], "groups": {}}})
    group = group_from_dict(d)
    assert [s.name for s in group.all_params()] == ["p", "antiwindup", "s"]
    with pytest.raises(ReconfigureError, match="parameter 'q' has type 'float'"):
        group_from_dict({"parameters": [{"name": "q", "type": "float"}]})
    with pytest.raises(ReconfigureError, match="not a dynamic_reconfigure group tree"):
        group_from_dict(["p"])


def test_server_tree_and_filter():
    names = ["/ptrz/pan_position_controller/pid", "/ptrz/tilt_position_controller/pid", "/cam"]
    assert server_tree(names) == {"cam": {}, "ptrz": {"pan_position_controller": {"pid": {}},
                                                      "tilt_position_controller": {"pid": {}}}}
    assert matches("/ptrz/pan_position_controller/pid", "PAN pid")
    assert not matches("/ptrz/pan_position_controller/pid", "tilt")


def test_format_value():
    assert format_value(-0.0) == "0" and format_value(0.01) == "0.01" and format_value(True) == "true"
