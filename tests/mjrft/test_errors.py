"""mjrft's errors (mjrft.errors): the checks return a valid number as a float and name a bad one with its value;
an unknown name lists every valid choice and is caught as ValueError and KeyError."""

from __future__ import annotations

import pytest

from mjrft.errors import MjrftError, UnknownNameError, check_finite, check_positive, unknown


def test_valid_numbers_come_back_as_floats():
    assert check_positive("resolution", 1) == 1.0 and isinstance(check_positive("resolution", 1), float)
    assert check_positive("yield_displacement", 0, allow_zero=True) == 0.0
    assert check_finite("surface", "-0.25") == -0.25


@pytest.mark.parametrize("check,value,message", [
    (lambda v: check_positive("resolution", v), -0.01, "resolution must be finite and > 0, got -0.01"),
    (lambda v: check_positive("resolution", v), 0, "resolution must be finite and > 0, got 0"),
    (lambda v: check_positive("damping_time", v, allow_zero=True), float("inf"),
     "damping_time must be finite and >= 0, got inf"),
    (lambda v: check_positive("resolution", v), "fine", "resolution must be a number, got 'fine'"),
    (lambda v: check_finite("surface", v), float("nan"), "surface must be finite, got nan"),
    (lambda v: check_finite("surface", v), None, "surface must be a number, got None"),
])
def test_a_bad_number_is_named_with_its_value(check, value, message):
    with pytest.raises(ValueError) as err:
        check(value)
    assert str(err.value) == message


def test_an_unknown_name_lists_the_valid_choices_sorted():
    err = unknown("medium", "mud", ["poppy_cp", "glass3_cp"])
    assert isinstance(err, UnknownNameError) and isinstance(err, ValueError) and isinstance(err, KeyError)
    assert isinstance(err, MjrftError)
    assert str(err) == "unknown medium 'mud'; valid choices: glass3_cp, poppy_cp"  # not quoted as a KeyError's
    with pytest.raises(KeyError):
        raise err
