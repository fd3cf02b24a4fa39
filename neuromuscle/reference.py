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

from .analysis.module3 import ce_velocity, floored_capacity, force_length
from .model.extensions.twin import Observables, StateModulation
from .protocols.lengths import LengthTrace
from .parameters import ParameterSet
from .parameters.specs import registry

_ATOL = np.array([1e-12, 1e-11, 1e-14, 1e-13, 1e-14, 1e-9, 1e-13])

#: Module 3's state here is u = (Xm - XCE) - (Xm - Xm(0)) = Xm(0) - XCE (mm), whose derivative -VCE is continuous
#: in t; the SE extension Xm - XCE (eq 9) is u + Xm(t) - Xm(0), with Xm(t) the length NEURON plays (linear between
#: samples), so the muscle's velocity enters through Xm itself, never a sampled slope.  At a constant length u is
#: the extension exactly, which resolves the tiny forces at rest that an absolute CE length (~ -8 mm) would hide
#: below the tolerance.  (With the extension itself as the state, driven by Xm's slope, the right-hand side would
#: jump at every 0.1 ms sample of a random length, which costs Radau ~16 steps per sample.)
_SE_STATE = 6


@dataclass
class ReferenceResult:
    """t (ms), force (N), A, Atil, the five Ca states (M) and an extension's states (one row each; a
    StateModulation's) on the requested grid."""

    t_ms: np.ndarray
    force_N: np.ndarray
    A: np.ndarray
    atil: np.ndarray
    ca_M: dict[str, np.ndarray]
    extension_states: np.ndarray | None = None


def _flat_values(params: ParameterSet) -> dict[str, float]:
    """The set's values under their qualified names and their flat Kim aliases, as a plain dict: the right-hand
    side reads ~40 of them per call, and a ParameterSet resolves each alias through the registry."""
    aliases = registry().aliases
    return {**params.values, **{a: params.values[q] for a, q in aliases.items() if q in params.values}}


def _phi(x: float, p: Mapping[str, float]) -> float:
    return p["phi1"] * x + p["phi2"] if x <= p["g1"] else p["phi3"] * x + p["phi4"]


def activation(atil: float, t: float, x: float, v: float, p: Mapping[str, float],
               movement: tuple[bool, bool], onset: float | None, at_onset: bool = True) -> float:
    """A from Atil (eq 8), with eq 19 (movement[0]) and eq 20 (movement[1]) when on and t > onset (ms), or at
    the onset itself when ``at_onset`` says the movement has started; x mm, v mm/s.  A is floored at 1e-3 while
    eq 19 is active; a non-positive eq 20 divisor gives A = 0."""
    at = max(atil, 0.0)
    moving = onset is not None and (t > onset or (at_onset and t >= onset))
    eq19, eq20 = (moving and movement[0]), (moving and movement[1])
    a_t = p["alpha"] + p["alpha1"] * (1.0 + np.tanh((t - onset - p["alpha2"]) / p["alpha3"])) if eq19 \
        else p["alpha"]
    A = at ** a_t
    if eq20 and x <= p["g1"] and v >= 0.0:
        d = (1.0 + p["beta"] * _phi(x, p)) * (1.0 + p["gamma"] * v)
        A = A / d if d > 0.0 else 0.0
    return max(A, 1e-3) if eq19 else A


#: The modulation ports of the mechanisms and their neutral values (an extension's twin supplies functions of t).
NEUTRAL_PORTS = {"release_gain": 1.0, "uptake_gain": 1.0, "tauA_gain": 1.0, "force_offset": 0.0,
                 "C1_shift": 0.0, "capacity_gain": 1.0}


def _port(mod: Mapping[str, Callable[[float], float]], name: str, t: float) -> float:
    return float(mod[name](t)) if name in mod else NEUTRAL_PORTS[name]


def _ports(mod: Mapping[str, Callable[[float], float]] | StateModulation, t: float, y: np.ndarray,
           obs: Observables) -> dict[str, float]:
    """Every port's value at t: an extension's functions of t, or of its extra states y[7:]."""
    if isinstance(mod, StateModulation):
        return {**NEUTRAL_PORTS, **{n: float(f(t, y[7:], obs)) for n, f in mod.ports.items()}}
    return {n: _port(mod, n, t) for n in NEUTRAL_PORTS}


def _rhs(t: float, y: np.ndarray, p: Mapping[str, float], spikes: np.ndarray, trace: LengthTrace,
         lencomp: bool, movement: tuple[bool, bool],
         mod: Mapping[str, Callable[[float], float]] | StateModulation, seg_start: float) -> list[float]:
    CaSR, CaSRCS, CaSP, CaSPB, CaSPT, At, u = y[:7]  # u = y[_SE_STATE]
    x = float(np.interp(t, trace.t_ms, trace.xm_mm))
    ext = u + (x - float(trace.xm_mm[0]))  # the SE extension Xm - XCE (mm): see _SE_STATE
    v = float(np.interp(t, trace.t_ms, trace.velocity_mm_s))  # the played Vm of eq 20
    # the segment that ends at the onset runs without eqs 19-20 up to and including it (its solver evaluates the
    # right-hand side at the segment's end); the next one starts with them
    A = activation(At, t, x, v, p, movement, trace.onset_ms, at_onset=t > seg_start)
    F = p["P0"] * p["KSE"] * max(ext, 0.0)
    obs = Observables(A, x, v, F, p)
    port = _ports(mod, t, y, obs)
    d = t - spikes[spikes <= t]
    s = float(np.sum((1.0 - np.exp(-d / p["tau1"])) * np.exp(-d / p["tau2"])))
    R = port["release_gain"] * CaSR * p["Rmax"] * s
    c = max(CaSP, 0.0)
    z = (c * p["K"]) ** 2
    U = port["uptake_gain"] * p["Umax"] * (z / (1.0 + c * p["K"] + z)) ** 2
    K5 = p["K5i"] * (_phi(x, p) if lencomp else 1.0)
    K6 = p["K6i"] / (1.0 + 5.0 * At)
    sr = p["K1"] * CaSR * (p["CS0"] - CaSRCS) - p["K2"] * CaSRCS
    sb = p["K3"] * CaSP * (p["B0"] - CaSPB) - p["K4"] * CaSPB
    st = K5 * CaSP * (p["T0"] - CaSPT) - K6 * CaSPT
    xt = CaSPT / p["T0"]
    ainf = 0.5 * (1.0 + np.tanh((xt - p["C1"] - port["C1_shift"]) / p["C2"]))
    tau = port["tauA_gain"] * p["C3"] / np.cosh((xt - p["C4"]) / (2.0 * p["C5"]))
    Fc = floored_capacity(float(force_length(x, p["g1"], p["g2"], p["P0"])) * A * port["capacity_gain"], p["P0"])
    extra = list(mod.rhs(t, y[7:], obs)) if isinstance(mod, StateModulation) else []
    return [-sr - R + U, sr, -st - sb + R - U, sb, st, (ainf - At) / tau, -ce_velocity(F, Fc, p) / 1000.0,
            *extra]


def _initial_state(p: Mapping[str, float], trace: LengthTrace, kind: str, movement: tuple[bool, bool]) -> np.ndarray:
    """y0: the published initial state of Kim et al. 2015 (all SR calcium free, nothing bound, no force), or the
    resting steady
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
    fc = float(force_length(x0, p["g1"], p["g2"], p["P0"])) * activation(atil, 0.0, x0, 0.0, p, movement,
                                                                            trace.onset_ms)
    fc = floored_capacity(fc, p["P0"])
    return np.array([casr, p["CaSR0"] - casr, 0.0, 0.0, 0.0, atil, fc / (p["P0"] * p["KSE"])])


def reference_simulate(params: ParameterSet, spikes_ms: np.ndarray, length: LengthTrace | float,
                       duration_ms: float, *, record_dt_ms: float = 0.025, length_compensation: bool = True,
                       movement_compensation: bool = False, rtol: float = 1e-8,
                       modulation: Mapping[str, Callable[[float], float]] | StateModulation | None = None,
                       initial_state: str = "rest", movement_depression: bool | None = None,
                       lengthening_divisor: bool | None = None) -> ReferenceResult:
    """Integrate the model with scipy Radau from the published initial state (ms, mm, N, M).  ``modulation``
    maps port names (``NEUTRAL_PORTS``) to functions of t (ms), or is a ``StateModulation`` whose states are
    integrated with the model's: an extension's twin (its ``reference_modulation``); the output force is the SE
    force plus force_offset (N).  Eq 19 and eq 20 each follow ``movement_compensation`` unless
    ``movement_depression`` / ``lengthening_divisor`` say otherwise."""
    mod = modulation if isinstance(modulation, StateModulation) else dict(modulation or {})
    unknown = set(mod.ports if isinstance(mod, StateModulation) else mod) - set(NEUTRAL_PORTS)
    if unknown:
        raise ValueError(f"unknown modulation ports {sorted(unknown)}; known: {sorted(NEUTRAL_PORTS)}")
    movement = (movement_compensation if movement_depression is None else movement_depression,
                movement_compensation if lengthening_divisor is None else lengthening_divisor)
    trace = length if isinstance(length, LengthTrace) else LengthTrace.isometric(float(length), duration_ms)
    spikes = np.asarray(spikes_ms, dtype=float)
    p = _flat_values(params)
    y0 = _initial_state(p, trace, initial_state, movement)
    atol = _ATOL
    if isinstance(mod, StateModulation):
        y0 = np.concatenate([y0, np.asarray(mod.y0, dtype=float)])
        atol = np.concatenate([_ATOL, np.full(len(mod.y0), 1e-10)])
    t_eval = np.arange(0.0, duration_ms + 0.5 * record_dt_ms, record_dt_ms)
    # integrate piecewise between spikes (and at eq 19-20's movement onset) so the solver never steps across a
    # release onset or the movement clock's switch
    stops = [trace.onset_ms] if trace.onset_ms is not None and 0 < trace.onset_ms < duration_ms else []
    edges = np.unique(np.concatenate([[0.0], spikes[(spikes > 0) & (spikes < duration_ms)], stops,
                                      [duration_ms]]))
    ys, ts = [], []
    y = y0
    for a, b in zip(edges[:-1], edges[1:]):
        sel = t_eval[(t_eval >= a) & (t_eval < b)] if b < duration_ms else t_eval[t_eval >= a]
        # integrate to b itself: the next segment starts from the state at b, not at the last sample before it
        ask = sel if sel.size and sel[-1] >= b else np.append(sel, b)
        sol = solve_ivp(_rhs, (a, b), y, method="Radau", rtol=rtol, atol=atol, t_eval=ask, max_step=1.0,
                        args=(p, spikes, trace, length_compensation, movement, mod, a))
        if sol.status != 0:
            raise RuntimeError(f"reference integration failed on {a}..{b} ms: {sol.message}")
        ys.append(sol.y[:, :sel.size])
        ts.append(sol.t[:sel.size])
        y = sol.y[:, -1]
    Y = np.concatenate(ys, axis=1)
    t = np.concatenate(ts)
    x = trace.at(t)
    v = trace.velocity_at(t)
    A = np.array([activation(a, ti, xi, vi, p, movement, trace.onset_ms, at_onset=False)
                  for a, ti, xi, vi in zip(Y[5], t, x, v)])
    Y[_SE_STATE] = Y[_SE_STATE] + (x - float(trace.xm_mm[0]))  # u -> the SE extension Xm - XCE (mm)
    fse = p["P0"] * p["KSE"] * np.maximum(Y[_SE_STATE], 0.0)
    F = fse + np.array([_ports(mod, ti, Y[:, i], Observables(A[i], x[i], v[i], fse[i], p))["force_offset"]
                        for i, ti in enumerate(t)])
    names = ("CaSR", "CaSRCS", "CaSP", "CaSPB", "CaSPT")
    return ReferenceResult(t, F, A, Y[5], {n: Y[i] for i, n in enumerate(names)}, Y[7:])
