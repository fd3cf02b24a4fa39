"""Causes of over-tolerance sweep comparisons: the timing-tolerant difference, and ``explain`` naming CVODE's own
error, a switch transient, the fixed step's first-order error, and a difference nothing accounts for."""

import numpy as np
import pytest

from neuromuscle import Simulator, kim_excitation, simulate
from neuromuscle.bench.sweep import RECORD_DT_MS, SweepSettings, run_protocol
from neuromuscle.bench.sweep_draws import draw
from neuromuscle.bench.sweep_explain import classify, explain, timing_tolerant_pct
from neuromuscle.bench.sweep_summary import fixed_vs_cvode_pct
from neuromuscle.bench.sweep_protocols import sweep_protocols


def test_timing_tolerance_forgives_a_shift_within_the_window_only():
    t = np.arange(0.0, 10.0, 0.025)
    fine = np.where(t >= 5.0, 1.0, 0.0)              # a step at 5 ms, sampled every 0.025 ms
    coarse = np.where(t[::20] >= 5.0 - 0.025, 1.0, 0.0)[:fine[::20].size]
    assert timing_tolerant_pct(coarse, fine, 20, 1) == 0.0
    late = np.where(t[::20] >= 4.5, 1.0, 0.0)         # the step 0.5 ms early: one sample off by the whole step
    assert timing_tolerant_pct(late, fine, 20, 1) == pytest.approx(100.0)
    assert timing_tolerant_pct(fine[::20] * 0.98, fine, 20, 1) == pytest.approx(2.0)
    with pytest.raises(ValueError, match="too short"):
        timing_tolerant_pct(np.zeros(30), np.zeros(100), 20, 1)


def _runs(ct09, index, name):
    d = draw(ct09, 0, index)
    p = next(p for p in sweep_protocols(d.params["g1"], d.length_seed, d.movement_compensation, True)
             if p.name == name)
    settings = SweepSettings(n_draws=1, short=True)
    return d.params, p, {m: run_protocol(d.params, index, p, m, settings)[1] for m in ("fixed", "cvode")}


def test_the_ramp_onset_of_a_silent_unit_is_no_longer_over_the_tolerance(ct09):
    # draw 23: a nearly silent unit (A 2e-7) whose A jumps to eq 19's floor at the ramp's onset: 4.8 % of peak
    # apart, once classified switch_timing; it was CVODE's error (rtol weighed |XCE| ~ 10 mm; fixed steps at dt,
    # dt/2, dt/4 agreed to 0.001 %).  With Module 3's state relative to the initial length both agree
    params, p, f = _runs(ct09, 23, "ramp50_mc")
    assert fixed_vs_cvode_pct(f["fixed"], f["cvode"]) < 0.1
    e = explain(params, p, f["fixed"], f["cvode"], 0.025, RECORD_DT_MS)
    assert max(e["fixed_half_pct"], e["fixed_quarter_pct"], e["cvode_rtol_pct"]) < 0.1, e


def test_a_tetanus_stretched_across_the_optimum_is_no_longer_over_the_tolerance(ct09):
    # draw 25: a 40 Hz tetanus stretched at 200 mm/s with eqs 19-20 on, Xm crossing the optimum (eq 20 switching
    # off) within a fixed step: 1.6 % at dt 0.025 ms, once classified first_order; the step is now split there
    params, p, f = _runs(ct09, 25, "ramp200_mc")
    raw = fixed_vs_cvode_pct(f["fixed"], f["cvode"])
    assert raw < 0.5
    e = explain(params, p, f["fixed"], f["cvode"], 0.025, RECORD_DT_MS)
    assert e["fixed_quarter_pct"] < raw and e["fixed_quarter_pct"] < 0.2, e


def test_the_regenerative_twitch_of_draw_524_is_now_caught_by_the_fixed_step(ct09):
    # draw 524: C1 doubled puts Ainf's threshold where K6's cooperativity (K6i / (1 + 5 Atil)) makes the second
    # twitch of a 10 Hz train regenerative (CVODE and SciPy: 6.1 N).  With K6 reading Atil of the step's start the
    # fixed step missed it (1.6 N, 98 % of peak off; 5.9 N only at dt 0.001 ms); Atil extrapolated to the step's
    # middle catches it at dt 0.025 ms.  The difference was 0.58 % of peak at 155770b, 1.08 % with the CE substeps
    # of cc67d50, which held A of the step's end over every substep where F follows eq 11's asymptote down as A
    # collapses; with A interpolated across the substeps 0.56 %
    _, _, f = _runs(ct09, 524, "train10")
    assert f["cvode"].max() > 6.0 and f["fixed"].max() > 6.0 and fixed_vs_cvode_pct(f["fixed"], f["cvode"]) < 0.7


def test_evidence_nothing_accounts_for_is_unexplained_and_the_order_is_kept():
    base = {"timing_pct": 5.0, "fixed_half_pct": 5.0, "fixed_quarter_pct": 5.0, "fixed_quarter_timing_pct": 5.0,
            "cvode_rtol_pct": 0.1}
    assert classify(base, 5.0) == "unexplained"
    assert classify({**base, "cvode_rtol_pct": 3.0}, 5.0) == "ill_conditioned"
    assert classify({**base, "timing_pct": 0.5}, 5.0) == "switch_timing"
    # shrinking with dt and within 1 % at dt/4: first order, even where a time shift would also hide it
    assert classify({**base, "timing_pct": 0.5, "fixed_half_pct": 2.0, "fixed_quarter_pct": 0.9}, 5.0) == "first_order"
    # within 1 % at dt/4 but not shrinking monotonically: not first order
    assert classify({**base, "fixed_half_pct": 6.0, "fixed_quarter_pct": 0.9}, 5.0) == "unexplained"
    # a tight CVODE agreeing with the fixed step and not with the default CVODE: CVODE's own error, named first
    assert classify({**base, "tight_fixed_pct": 0.3, "tight_cvode_pct": 4.0, "fixed_half_pct": 2.0,
                     "fixed_quarter_pct": 0.9}, 5.0) == "cvode"
    assert classify({**base, "tight_fixed_pct": 1.5, "tight_cvode_pct": 4.0}, 5.0) == "unexplained"
    assert classify({**base, "tight_fixed_pct": 0.3, "tight_cvode_pct": 0.8}, 5.0) == "unexplained"


def test_cvode_at_the_old_rtol_is_named_as_the_integrator_in_error(ct09):
    # draw 476 (peak 0.0018 N, random length): at rtol 1e-6 CVODE was 1.03 % of peak off where the SE takes up
    # slack (rtol |dxce|, |dxce| ~ 4 mm); the fixed step is within 0.3 % of a tight CVODE
    d = draw(ct09, 0, 476)
    p = next(p for p in sweep_protocols(d.params["g1"], d.length_seed, d.movement_compensation, True)
             if p.name == "random_length")
    f = {m: simulate(d.params, p.spikes_ms, p.length, p.duration_ms, simulator=sim, record=("force.F",),
                     record_dt_ms=RECORD_DT_MS, excitation=kim_excitation()).force_N
         for m, sim in (("fixed", Simulator()), ("cvode", Simulator(method="cvode", rtol=1e-6)))}
    e = explain(d.params, p, f["fixed"], f["cvode"], 0.025, RECORD_DT_MS)
    assert e["cause"] == "cvode" and e["tight_fixed_pct"] < 0.5 < 1.0 < e["tight_cvode_pct"], e
