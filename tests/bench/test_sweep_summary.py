"""The sweep's summariser detects each kind of failure (so the sweep's checks can fail), and passes a clean set."""

import numpy as np
import pytest

from neuromuscle import NumericalError
from neuromuscle.bench.sweep_summary import comparison, error_status, failures, run_record, summarise

T = np.linspace(0.0, 1.0, 101)
FORCE = 3.0 * np.sin(np.pi * T) ** 2  # N


def _clean(draw=0, protocol="twitch"):
    runs = [run_record(draw, protocol, m, 100.0, 0.1, force_N=FORCE) for m in ("fixed", "cvode")]
    return runs, [comparison(draw, protocol, FORCE, FORCE * 1.001)]


def test_a_clean_sweep_passes():
    runs, comparisons = _clean()
    s = summarise(runs, comparisons, seed=3, n_draws=1, n_runs_expected=2)
    assert s["failures"] == [] and s["seed"] == 3 and s["n_runs"] == 2
    assert s["worst_fixed_vs_cvode_pct"] == {"pct": pytest.approx(0.1 * 3 / 3.003, rel=1e-6), "draw": 0,
                                             "protocol": "twitch", "peak_N": pytest.approx(3.003)}
    assert s["per_protocol"]["twitch"]["fixed_vs_cvode_pct"]["n"] == 1 and s["wall_s"]["median"] == 0.1


def test_an_injected_nan_is_counted_as_nonfinite():
    bad = FORCE.copy()
    bad[40] = np.nan
    runs, comparisons = _clean()
    runs.append(run_record(1, "twitch", "fixed", 100.0, 0.1, force_N=bad))
    comparisons.append(comparison(1, "twitch", bad, FORCE))
    s = summarise(runs, comparisons, seed=0, n_draws=2)
    assert s["nonfinite"] == 1 and s["draws_with"]["nonfinite"] == [1]
    assert "1 run(s) gave non-finite values" in s["failures"]
    assert np.isnan(s["worst_fixed_vs_cvode_pct"]["pct"]) and any("differ" in f for f in s["failures"])


def test_negative_force_exceptions_hangs_and_large_differences_fail():
    runs, comparisons = _clean()
    runs.append(run_record(2, "ramp50", "fixed", 100.0, 0.1, force_N=FORCE - 0.01))
    runs.append(run_record(3, "train10", "cvode", 100.0, 0.2, error=ZeroDivisionError("float division by zero")))
    budget = NumericalError("parameter set 'x': CVODE spent its wall-time budget of 10 s and reached only t = 12.5 "
                            "ms of 400 ms (atol 0.001); raise max_wall_s")
    runs.append(run_record(4, "twitch", "cvode", 400.0, 10.0, error=budget, t_reached_ms=12.5))
    runs.append(run_record(5, "twitch", "cvode", 400.0, 99.0, error="killed after 99 s", status="timeout"))
    comparisons.append(comparison(6, "random_length", FORCE, FORCE * 1.02))
    s = summarise(runs, comparisons, seed=0, n_draws=7, n_runs_expected=14)
    assert (s["negative_force"], s["exceptions"], s["hangs"], s["nonfinite"]) == (1, 1, 2, 0)
    assert s["exceptions_by_class"] == {"ZeroDivisionError: float division by zero": 1}
    assert [(h["draw"], h["t_reached_ms"]) for h in s["examples"]["hangs"]] == [(4, 12.5), (5, None)]
    assert s["worst_fixed_vs_cvode_pct"]["draw"] == 6 and s["worst_fixed_vs_cvode_pct"]["pct"] > 1.9
    assert s["per_protocol"]["random_length"]["n_over_tolerance"] == 1 and s["n_over_tolerance"] == 1
    assert s["per_protocol"]["twitch"]["hangs"] == 2 and s["per_protocol"]["train10"]["exceptions"] == 1
    assert len(s["failures"]) == 5  # exceptions, hangs, negative force, difference, missing runs
    assert "6 runs recorded of 14 expected" in s["failures"]


def test_error_status_tells_budget_stops_and_nonfinite_runs_from_other_errors():
    assert error_status("x: CVODE took its budget of 20 steps and reached only t = 3 ms of 400 ms") == "budget_stop"
    assert error_status("unit: non-finite force.F at t = 3.000 ms (fixed, dt 0.025 ms)") == "nonfinite"
    assert error_status("x: CVODE failed at t = 3 ms of 400 ms") == "exception"
    assert failures(summarise([], [], seed=0, n_draws=0)) == ["no fixed-vs-CVODE comparison"]


def test_explained_differences_are_counted_by_cause_and_only_unexplained_ones_fail():
    runs, comparisons = _clean()
    timing = comparison(1, "ramp50_mc", FORCE, FORCE * 1.04)
    timing["explained"] = {"cause": "switch_timing", "timing_pct": 0.01}
    first = comparison(2, "train40", FORCE, FORCE * 1.02)
    first["explained"] = {"cause": "first_order", "fixed_quarter_pct": 0.5}
    s = summarise(runs, comparisons + [timing, first], seed=0, n_draws=3)
    assert s["failures"] == [] and s["n_over_tolerance"] == 2
    assert s["over_tolerance_by_cause"] == {"switch_timing": 1, "first_order": 1}
    assert s["worst_fixed_vs_cvode_pct"]["draw"] == 1 and s["worst_unexplained_pct"] is None
    assert s["worst_by_cause"]["first_order"]["explained"]["fixed_quarter_pct"] == 0.5
    unexplained = comparison(3, "twitch", FORCE, FORCE * 1.03)  # not examined: unexplained
    s = summarise(runs, comparisons + [timing, first, unexplained], seed=0, n_draws=4)
    assert s["worst_unexplained_pct"]["draw"] == 3 and s["over_tolerance_by_cause"]["unexplained"] == 1
    assert any("1 unexplained" in f and "draw 3" in f for f in s["failures"])
