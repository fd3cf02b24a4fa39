"""An independent SciPy integration of the same model (eqs 1-12, 18-20), to keep the NMODL honest.

Written from the spec, not from the mod files: the release sums over the spike history directly (eq 3 as
printed, no recursive kernels), the right-hand side is one function of all states, and scipy's Radau
integrates it at tight tolerances.  Slow by design; use it for tests and verification only.
Units as in the mechanisms: ms, M, mm, N, mm/s.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping

import numpy as np
from scipy.integrate import solve_ivp

from .analysis.module3 import ce_velocity, force_length
from .protocols.lengths import LengthTrace
from .parameters import ParameterSet

_ATOL = np.array([1e-12, 1e-11, 1e-14, 1e-13, 1e-14, 1e-9, 1e-13])


@dataclass
class ReferenceResult:
    """t (ms), force (N), A, Atil and the five Ca states (M) on the requested grid."""

    t_ms: np.ndarray
    force_N: np.ndarray
    A: np.ndarray
    atil: np.ndarray
    ca_M: dict[str, np.ndarray]


def _phi(x: float, p: ParameterSet) -> float:
    return p["phi1"] * x + p["phi2"] if x <= p["g1"] else p["phi3"] * x + p["phi4"]


def activation(atil: float, t: float, x: float, v: float, p: ParameterSet, movcomp: bool,
               onset: float | None) -> float:
    """A from Atil (eq 8), with eqs 19-20 when movcomp and t >= onset (ms); x mm, v mm/s."""
    at = max(atil, 0.0)
    if not movcomp or onset is None or t < onset:
        return at ** p["alpha"]
    a_t = p["alpha"] + p["alpha1"] * (1.0 + np.tanh((t - onset - p["alpha2"]) / p["alpha3"]))
    A = at ** a_t
    if x <= p["g1"] and v >= 0.0:
        A /= (1.0 + p["beta"] * _phi(x, p)) * (1.0 + p["gamma"] * v)
    return max(A, 1e-3)


#: The modulation ports of the mechanisms and their neutral values (an extension's twin supplies functions of t).
NEUTRAL_PORTS = {"release_gain": 1.0, "uptake_gain": 1.0, "tauA_gain": 1.0, "force_offset": 0.0}


def _port(mod: Mapping[str, Callable[[float], float]], name: str, t: float) -> float:
    return float(mod[name](t)) if name in mod else NEUTRAL_PORTS[name]


def _rhs(t: float, y: np.ndarray, p: ParameterSet, spikes: np.ndarray, trace: LengthTrace,
         lencomp: bool, movcomp: bool, mod: Mapping[str, Callable[[float], float]]) -> list[float]:
    CaSR, CaSRCS, CaSP, CaSPB, CaSPT, At, ext = y
    d = t - spikes[spikes <= t]
    s = float(np.sum((1.0 - np.exp(-d / p["tau1"])) * np.exp(-d / p["tau2"])))
    R = _port(mod, "release_gain", t) * CaSR * p["Rmax"] * s
    c = max(CaSP, 0.0)
    z = (c * p["K"]) ** 2
    U = _port(mod, "uptake_gain", t) * p["Umax"] * (z / (1.0 + c * p["K"] + z)) ** 2
    x = float(np.interp(t, trace.t_ms, trace.xm_mm))
    v = float(np.interp(t, trace.t_ms, trace.velocity_mm_s))  # the played Vm of eq 20
    # the SE sees the length NEURON plays (linear between samples): its exact slope, so that the integral of
    # the muscle's velocity is Xm itself (a sampled velocity would make the SE drift)
    k = min(max(int(np.searchsorted(trace.t_ms, t, side="right")) - 1, 0), trace.t_ms.size - 2)
    dx = 1000.0 * (trace.xm_mm[k + 1] - trace.xm_mm[k]) / (trace.t_ms[k + 1] - trace.t_ms[k])
    K5 = p["K5i"] * (_phi(x, p) if lencomp else 1.0)
    K6 = p["K6i"] / (1.0 + 5.0 * At)
    sr = p["K1"] * CaSR * (p["CS0"] - CaSRCS) - p["K2"] * CaSRCS
    sb = p["K3"] * CaSP * (p["B0"] - CaSPB) - p["K4"] * CaSPB
    st = K5 * CaSP * (p["T0"] - CaSPT) - K6 * CaSPT
    xt = CaSPT / p["T0"]
    ainf = 0.5 * (1.0 + np.tanh((xt - p["C1"]) / p["C2"]))
    tau = _port(mod, "tauA_gain", t) * p["C3"] / np.cosh((xt - p["C4"]) / (2.0 * p["C5"]))
    A = activation(At, t, x, v, p, movcomp, trace.onset_ms)
    F = p["P0"] * p["KSE"] * max(ext, 0.0)
    Fc = float(force_length(x, p["g1"], p["g2"], p["P0"])) * A
    # the SE extension Xm - XCE (mm) is the state here: it resolves the tiny forces at rest that an
    # absolute CE length (~ -8 mm) would hide below the tolerance
    return [-sr - R + U, sr, -st - sb + R - U, sb, st, (ainf - At) / tau, (dx - ce_velocity(F, Fc, p)) / 1000.0]


def _initial_state(p: ParameterSet, trace: LengthTrace, kind: str, lencomp: bool, movcomp: bool) -> np.ndarray:
    """y0: seed 001's published state (all SR calcium free, nothing bound, no force), or the resting steady
    state: no sarcoplasmic calcium, the SR's CaSR0 shared with calsequestrin (eq 2 at rest), Atil at its steady
    state for [CaSPT] = 0 (eq 8), and the SE carrying the CE's force at the initial length (eqs 9-12)."""
    if kind == "published":
        return np.array([p["CaSR0"], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    if kind != "rest":
        raise ValueError(f"initial_state must be 'rest' or 'published', got {kind!r}")
    b = p["K1"] * (p["CS0"] - p["CaSR0"]) + p["K2"]
    casr = (-b + np.sqrt(b * b + 4.0 * p["K1"] * p["K2"] * p["CaSR0"])) / (2.0 * p["K1"])
    atil = 0.5 * (1.0 + np.tanh((0.0 - p["C1"]) / p["C2"]))
    x0 = float(trace.xm_mm[0])
    fc = float(force_length(x0, p["g1"], p["g2"], p["P0"])) * activation(atil, 0.0, x0, 0.0, p, movcomp,
                                                                            trace.onset_ms)
    return np.array([casr, p["CaSR0"] - casr, 0.0, 0.0, 0.0, atil, fc / (p["P0"] * p["KSE"])])


def reference_simulate(params: ParameterSet, spikes_ms: np.ndarray, length: LengthTrace | float,
                       duration_ms: float, *, record_dt_ms: float = 0.025, length_compensation: bool = True,
                       movement_compensation: bool = False, rtol: float = 1e-8,
                       modulation: Mapping[str, Callable[[float], float]] | None = None,
                       initial_state: str = "rest") -> ReferenceResult:
    """Integrate the model with scipy Radau from the published initial state (ms, mm, N, M).  ``modulation``
    maps port names (``NEUTRAL_PORTS``) to functions of t (ms): an extension's twin (its
    ``reference_modulation``); the output force is the SE force plus force_offset(t) (N)."""
    mod = dict(modulation or {})
    unknown = set(mod) - set(NEUTRAL_PORTS)
    if unknown:
        raise ValueError(f"unknown modulation ports {sorted(unknown)}; known: {sorted(NEUTRAL_PORTS)}")
    trace = length if isinstance(length, LengthTrace) else LengthTrace.isometric(float(length), duration_ms)
    spikes = np.asarray(spikes_ms, dtype=float)
    p = params
    y0 = _initial_state(p, trace, initial_state, length_compensation, movement_compensation)
    t_eval = np.arange(0.0, duration_ms + 0.5 * record_dt_ms, record_dt_ms)
    # integrate piecewise between spikes so the solver never steps across a release onset
    edges = np.unique(np.concatenate([[0.0], spikes[(spikes > 0) & (spikes < duration_ms)], [duration_ms]]))
    ys, ts = [], []
    y = y0
    for a, b in zip(edges[:-1], edges[1:]):
        sel = t_eval[(t_eval >= a) & (t_eval < b)] if b < duration_ms else t_eval[t_eval >= a]
        # integrate to b itself: the next segment starts from the state at b, not at the last sample before it
        ask = sel if sel.size and sel[-1] >= b else np.append(sel, b)
        sol = solve_ivp(_rhs, (a, b), y, method="Radau", rtol=rtol, atol=_ATOL, t_eval=ask, max_step=1.0,
                        args=(p, spikes, trace, length_compensation, movement_compensation, mod))
        if sol.status != 0:
            raise RuntimeError(f"reference integration failed on {a}..{b} ms: {sol.message}")
        ys.append(sol.y[:, :sel.size])
        ts.append(sol.t[:sel.size])
        y = sol.y[:, -1]
    Y = np.concatenate(ys, axis=1)
    t = np.concatenate(ts)
    x = trace.at(t)
    v = trace.velocity_at(t)
    A = np.array([activation(a, ti, xi, vi, p, movement_compensation, trace.onset_ms)
                  for a, ti, xi, vi in zip(Y[5], t, x, v)])
    F = p["P0"] * p["KSE"] * np.maximum(Y[6], 0.0) + np.array([_port(mod, "force_offset", ti) for ti in t])
    names = ("CaSR", "CaSRCS", "CaSP", "CaSPB", "CaSPT")
    return ReferenceResult(t, F, A, Y[5], {n: Y[i] for i, n in enumerate(names)})
