"""Why a sweep comparison is over the tolerance (``neuromuscle bench sweep``): each fixed-vs-CVODE difference
above ``TOLERANCE_PCT`` is examined in the draw's own process by four further runs and named by the first of
these that accounts for it, in this order (all differences in % of the larger peak, N):

- ``"cvode"``: CVODE's own error: a tight CVODE (rtol ``TIGHT_RTOL``, atol 1e-5) agrees with the fixed step
  within the tolerance and not with the default CVODE (Module 3's state dxce grows with the length excursion, so
  rtol |dxce| can be a large part of a weak unit's force; sweep draws 7 and 23 were once named first_order);
- ``"first_order"``: the fixed step converges on CVODE as dt shrinks (dt, dt/2, dt/4 in decreasing order) and
  is within the tolerance at dt/4 (directly or timing-tolerant to dt): the fixed step's O(dt) error at
  this parameter set (use a smaller dt or CVODE for it);
- ``"switch_timing"``: within the tolerance once each fixed-step sample may be matched to CVODE anywhere within
  one fixed step of its time.  Eq 19's onset and eq 20's switch (the sign of Vm, Xm crossing the optimum) make
  A jump, and at near-zero force the SE goes slack and taut; the fixed step places such a switch on its step
  grid, CVODE where it falls.  At low activation the CE then moves within far less than a step, so the two
  forces differ by the whole transient for a sample or two;
- ``"ill_conditioned"``: CVODE itself moves by more than the tolerance when its rtol is 10 times looser: the
  model amplifies perturbations there (e.g. K6's cooperativity near the threshold of Ainf), so no integrator's
  answer is better than its own error;
- ``"unexplained"``: none of these.

The raw difference is still what the sweep reports as its worst; the cause says whether it is a known limit of
the fixed step or a finding.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..parameters import ParameterSet
from ..sim.simulator import Simulator
from .sweep_protocols import Protocol
from .sweep_summary import TOLERANCE_PCT, fixed_vs_cvode_pct

#: The order in which the causes are tested, "unexplained" last.
CAUSES = ("cvode", "first_order", "switch_timing", "ill_conditioned", "unexplained")
#: CVODE's rtol for the conditioning check: 10 times the Simulator default the sweep's runs use.
LOOSE_RTOL = 10 * Simulator.rtol
#: CVODE's rtol (with atol 1e-5) for the check of CVODE's own error.
TIGHT_RTOL = 1e-9


def timing_tolerant_pct(fixed_N: np.ndarray, cvode_fine_N: np.ndarray, stride: int, shift: int) -> float:
    """Largest difference (% of the larger peak) between each fixed-step sample ``fixed_N[i]`` and the CVODE trace
    ``cvode_fine_N`` (sampled ``stride`` times as often: fixed_N[i] is at cvode_fine_N[i * stride]) anywhere within
    ``shift`` fine samples of its time, taken as piecewise linear: 0 where the sample lies between the window's
    smallest and largest value."""
    f = np.asarray(fixed_N, dtype=float)
    c = np.asarray(cvode_fine_N, dtype=float)
    idx = np.arange(f.size) * stride
    if idx[-1] >= c.size:
        raise ValueError(f"fine trace of {c.size} samples is too short for {f.size} samples at stride {stride}")
    offsets = np.arange(-shift, shift + 1)
    window = c[np.clip(idx[:, None] + offsets[None, :], 0, c.size - 1)]
    gap = np.maximum(0.0, np.maximum(window.min(axis=1) - f, f - window.max(axis=1)))
    peak = float(max(f.max(), c.max()))
    return 0.0 if not gap.max() > 0.0 else 100.0 * float(gap.max()) / peak


def explain(params: ParameterSet, protocol: Protocol, fixed_N: np.ndarray, cvode_N: np.ndarray, dt_ms: float,
            record_dt_ms: float, tolerance_pct: float = TOLERANCE_PCT) -> dict[str, Any]:
    """The cause of one over-tolerance comparison (see the module docstring) and the evidence, each in % of peak:
    the difference timing-tolerant to one step at dt (``timing_pct``); the fixed step at dt/2 and dt/4 against
    CVODE (``fixed_half_pct``, ``fixed_quarter_pct``) and at dt/4 timing-tolerant to dt
    (``fixed_quarter_timing_pct``); CVODE at 10 times the default rtol against the default (``cvode_rtol_pct``;
    inf, with ``cvode_rtol_error``, when CVODE fails there); a tight CVODE (``TIGHT_RTOL``) against the fixed step
    and against the default CVODE (``tight_fixed_pct``, ``tight_cvode_pct``; inf if it fails)."""
    from ..errors import NumericalError
    from ..model.kim import kim_excitation
    from ..sim import simulate

    def force(sim: Simulator, rec_dt: float) -> np.ndarray:
        r = simulate(params, protocol.spikes_ms, protocol.length, protocol.duration_ms, simulator=sim,
                     record=("force.F",), record_dt_ms=rec_dt,
                     excitation=kim_excitation(movement_compensation=protocol.movement_compensation))
        return r.force_N

    # CVODE sampled every dt (not finer: NEURON 9.0.2 aborts on an assertion in global_microstep when CVODE
    # records every 0.00625 ms, a record time a rounding error short of a step's end)
    stride = int(round(record_dt_ms / dt_ms))
    fine = force(Simulator(method="cvode"), dt_ms)
    quarter = force(Simulator(method="fixed", dt_ms=dt_ms / 4), record_dt_ms)
    half = force(Simulator(method="fixed", dt_ms=dt_ms / 2), record_dt_ms)
    out: dict[str, Any] = {"timing_pct": timing_tolerant_pct(fixed_N, fine, stride, 1),
                           "fixed_half_pct": fixed_vs_cvode_pct(half, cvode_N),
                           "fixed_quarter_pct": fixed_vs_cvode_pct(quarter, cvode_N),
                           "fixed_quarter_timing_pct": timing_tolerant_pct(quarter, fine, stride, 1)}
    try:
        loose = force(Simulator(method="cvode", rtol=LOOSE_RTOL), record_dt_ms)
        out["cvode_rtol_pct"] = fixed_vs_cvode_pct(loose, fine[::stride][:loose.size])
    except NumericalError as exc:  # CVODE failing at a looser rtol is evidence too, not a reason to stop
        out["cvode_rtol_pct"] = float("inf")
        out["cvode_rtol_error"] = str(exc).splitlines()[0][:200]
    try:
        tight = force(Simulator(method="cvode", rtol=TIGHT_RTOL, atol=1e-5), record_dt_ms)
        n = min(tight.size, fixed_N.size, cvode_N.size)
        out["tight_fixed_pct"] = fixed_vs_cvode_pct(fixed_N[:n], tight[:n])
        out["tight_cvode_pct"] = fixed_vs_cvode_pct(cvode_N[:n], tight[:n])
    except NumericalError as exc:
        out["tight_fixed_pct"] = out["tight_cvode_pct"] = float("inf")
        out["tight_error"] = str(exc).splitlines()[0][:200]
    return {**out, "cause": classify(out, fixed_vs_cvode_pct(fixed_N, cvode_N), tolerance_pct)}


def classify(evidence: dict[str, Any], raw_pct: float, tolerance_pct: float = TOLERANCE_PCT) -> str:
    """The cause (``CAUSES``) that ``evidence`` (the fields ``explain`` measures, % of peak) gives a difference of
    ``raw_pct``: tested in the order of the module docstring, so a difference that shrinks with dt is first-order
    even where a time shift would also hide it (a phase lag in a fast twitch)."""
    if evidence.get("tight_fixed_pct", np.inf) <= tolerance_pct < evidence.get("tight_cvode_pct", 0.0):
        return "cvode"
    if min(evidence["fixed_quarter_pct"], evidence["fixed_quarter_timing_pct"]) <= tolerance_pct \
            and evidence["fixed_quarter_pct"] < evidence["fixed_half_pct"] < raw_pct:
        return "first_order"
    if evidence["timing_pct"] <= tolerance_pct:
        return "switch_timing"
    if evidence["cvode_rtol_pct"] > tolerance_pct:
        return "ill_conditioned"
    return "unexplained"
