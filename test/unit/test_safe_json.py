"""The one JSON reader of the suite (formats/safe_json): whatever a hostile sender makes is a
ValueError naming what is wrong, never a RecursionError, a float that was an integer, or NaN."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from dsr_graph.exceptions import JsonRefused
from dsr_graph.formats.safe_json import MAX_DEPTH, loads, loads_object


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("[" * 100_000, "not JSON"),
        ('{"a":' * 100_000, "not JSON"),
        ("[" * (MAX_DEPTH + 1) + "]" * (MAX_DEPTH + 1), f"deeper than {MAX_DEPTH}"),
        ('{"a": NaN}', "not JSON"),
        ('{"a": Infinity}', "not JSON"),
        ('{"a": -Infinity}', "not JSON"),
        ('{"lease": 1e309}', "infinity"),
        ('{"a": 123456789012345678901234567890}', "outside the 64-bit range"),
        ('{"a": [18446744073709551615]}', "outside the 64-bit range"),
        ("-9223372036854775809", "outside the 64-bit range"),
        ('{"a": "' + "9" * 5000 + '"}' + "x", "not JSON"),
        ('"\udc80"', "not JSON"),
    ],
)
def test_hostile_json_is_refused_by_name(text, fragment):
    with pytest.raises(JsonRefused, match=fragment) as refused:
        loads(text)
    assert isinstance(refused.value, ValueError)


def test_limits_count_utf8_bytes_not_characters():
    text = '"' + "é" * 10 + '"'  # 12 characters, 22 bytes
    assert loads(text, max_bytes=22) == "é" * 10
    with pytest.raises(JsonRefused, match="22 bytes exceeds the limit of 21"):
        loads(text, max_bytes=21)
    with pytest.raises(JsonRefused, match="22 bytes"):
        loads(text.encode(), max_bytes=21)


def test_what_is_valid_reads_as_the_standard_library_reads_it():
    text = '{"a": [1, -2, 2.5, 1e30, true, null, "x"], "b": {"c": 9223372036854775807}}'
    assert loads(text) == {
        "a": [1, -2, 2.5, 1e30, True, None, "x"],
        "b": {"c": 9223372036854775807},
    }
    nested = "[" * MAX_DEPTH + "]" * MAX_DEPTH
    assert loads(nested) is not None


def test_an_object_is_asked_for_by_name():
    with pytest.raises(JsonRefused, match="a JSON object was expected, got an array"):
        loads_object("[1]")
    assert loads_object('{"x": 1}') == {"x": 1}


json_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(-(2**63), 2**63 - 1)
    | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(), inner, max_size=4),
    max_leaves=30,
)


@given(json_values)
def test_any_valid_json_round_trips(value):
    import json

    assert loads(json.dumps(value)) == value
