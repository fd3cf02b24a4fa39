"""neuromuscle.validate: argument checks, and the one rule for spike times (refuse unsorted, never sort)."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.validate import check_spike_times, finite_number, positive_number, time_order_problem


def test_spike_times_in_order_come_back_as_a_float64_copy():
    given = np.array([0, 5, 12], dtype=np.int64)
    out = check_spike_times(given)
    assert out.dtype == np.float64 and out.tolist() == [0.0, 5.0, 12.0]
    out[0] = 99.0
    assert given[0] == 0
    assert check_spike_times([]).shape == (0,)
    assert check_spike_times(iter([1.0, 2.0])).tolist() == [1.0, 2.0]


@pytest.mark.parametrize("times, message", [
    ([10.0, 30.0, 20.0], r"^spike times must be strictly increasing: index 2 holds 20 ms after 30 ms "
                         r"\(not sorted: unsorted times are refused, never sorted silently\)$"),
    ([10.0, 20.0, 20.0], r"^spike times must be strictly increasing: index 2 repeats 20 ms of index 1 "
                         r"\(two equal times\)$"),
    ([5.0, -1.0], r"^spike times must lie in \[0, inf\) ms: index 1 holds -1 ms \(negative time\)$"),
    ([10.0, np.nan], r"^spike times contains non-finite values: index 1 holds nan$"),
    ([10.0, np.inf], r"non-finite values: index 1 holds inf"),
    ([[1.0, 2.0], [3.0, 4.0]], r"^spike times must be a 1-D sequence of times in ms, got shape \(2, 2\)$"),
    (5.0, r"^spike times must be a sequence of numbers \(ms\)"),
    (["a"], r"^spike times must be a sequence of numbers \(ms\)"),
])
def test_spike_times_refused_naming_where_index_and_value(times, message):
    with pytest.raises(InputError, match=message):
        check_spike_times(times)


def test_spike_times_name_and_unit_of_the_caller():
    with pytest.raises(InputError, match=r"^stimuli of trial 3 must be strictly increasing: index 1 holds "
                                         r"0\.1 s after 0\.2 s .*; 2 such steps in all$"):
        check_spike_times([0.2, 0.1, 0.3, 0.25], where="stimuli of trial 3", unit="s")


def test_time_order_problem_strict_and_non_decreasing():
    t = np.array([0.0, 1.0, 1.0, 2.0])
    assert time_order_problem(t, "x", "s", strict=False) is None
    assert "two equal times" in time_order_problem(t, "x", "s")
    assert time_order_problem(np.array([1.0, 0.5]), "x", "s", strict=False).startswith("x must be non-decreasing")
    assert time_order_problem(np.zeros(0), "x", "s") is None


def test_numbers():
    assert finite_number("a", 2) == 2.0 and positive_number("b", "3.5") == 3.5
    for bad in (True, "x", float("nan"), None):
        with pytest.raises(InputError, match="^a must be a finite number"):
            finite_number("a", bad)
    with pytest.raises(InputError, match=r"^b must be > 0, got 0\.0$"):
        positive_number("b", 0)
