"""Hatze's excitation and the triceps surae contraction of van Zandwijk et al. 1998 as components (mod/hatze_*.mod).

Time inside these models is in seconds, angles in rad, moments in N m (docs/reference/hatze.md).  Defaults:
Table 2 (excitation of subject 3), Table 4 (active state), Table 1 subject 3 (contraction).  Bounds: a decade
either side of the tables (the paper's 95 % intervals lie well inside).
"""

from __future__ import annotations

from typing import Any

from .component import Component, Param, Port, State

_T2 = "a decade either side of van Zandwijk et al. 1998 Table 2 (its 95 % intervals lie inside)"
_T4 = "van Zandwijk et al. 1998 Table 4 and eq 9 (q rises monotonically from q0 to 1)"
_T1 = "a decade either side of van Zandwijk et al. 1998 Table 1"


def _decade(name: str, unit: str, default: float, doc: str, source: str) -> Param:
    return Param(name, unit, default, default / 10.0, default * 10.0, doc, source)


_ACTIVE_STATE = (
    Param("q0", "1", 0.005, 0.0, 0.1, "resting active state", _T4),
    Param("rho2", "1", 1.05, 1.0, 10.0, "eq 9 damping (> 1: real roots)", _T4, lower_inclusive=False),
    Param("xicheck", "1", 2.90, 1.01, 10.0, "eq 9 length-dependence constant", _T4),
    Param("s", "1", 1.0, 0.1, 10.0, "eq 9 length-dependence exponent", _T4),
)


class HatzeExcitation(Component):
    """HatzeExc: eqs 6-9 of van Zandwijk et al. 1998, spikes -> beta (s^2) -> gamma (s^4) -> active state
    A = q (1).  Receives spikes
    (1 ms half-sine pulses; pulses may not overlap).  ``theta``: an ExcitationTheta (Table 2 if None)."""

    suffix = "HatzeExc"
    namespace = "hatze_exc"
    receives_spikes = True
    min_interval_ms = 1.0
    parameters = (
        _decade("theta1", "1/s", 3.50e5, "eq 6 damping", _T2),
        _decade("theta2", "1/s^2", 5.58e6, "eq 6 stiffness", _T2),
        _decade("theta3", "1/s", 1.85e4, "eq 7 damping", _T2),
        _decade("theta4", "1/s^2", 2.92e5, "eq 7 stiffness", _T2),
        _decade("theta5", "1/s^4", 4.57e14, "eq 9 scale of gamma", _T2),
        *_ACTIVE_STATE,
    )
    exposes = {"A": "1", "alpha": "1", "noverlap": "1", "xi": "1"}
    states = (State("b", "s^2", 1e-12), State("vb", "s", 1e-9), State("g", "s^4", 1e-18),
              State("vg", "s^3", 1e-15))

    def __init__(self, theta: Any = None, **overrides: float) -> None:
        if theta is None:
            from .hatze_parameters import load_theta

            theta = load_theta()
        super().__init__(**{n: float(getattr(theta, n)) for n in ("theta1", "theta2", "theta3", "theta4",
                                                                   "theta5")}, **overrides)


class HatzeTrend(Component):
    """HatzeTrend: eq 10 of van Zandwijk et al. 1998, a first-order trend of gamma driven by the rate nu
    (= rate / 100 Hz, RANGE:
    set or Vector.play) instead of spikes; exposes A = q (eq 9)."""

    suffix = "HatzeTrend"
    namespace = "hatze_trend"
    parameters = (
        _decade("m", "1/s", 7.94, "trend rate constant", "a decade either side of van Zandwijk et al. 1998 Table 3"),
        _decade("c", "s^4", 3.91e-14, "trend gain on gamma's raw scale", "a decade either side of van Zandwijk "
                "et al. 1998 "
                "Table 3 (converted to gamma's scale)"),
        _decade("theta5", "1/s^4", 4.57e14, "eq 9 scale of gamma", _T2),
        *_ACTIVE_STATE,
    )
    exposes = {"A": "1", "nu": "1"}
    states = (State("g", "s^4", 1e-18),)


class HatzeMTC(Component):
    """HatzeMTC: the angular triceps surae muscle-tendon complex of van Zandwijk et al. 1998, section 2.1.1.
    Output M (N m);
    input phi_mtc_offset (rad).  ``subject``: a Table 1 subject ("1".."4")."""

    suffix = "HatzeMTC"
    namespace = "hatze_mtc"
    output = "M"
    parameters = (
        _decade("k_see", "N*m/rad^2", 377.0, "SEE stiffness", _T1),
        _decade("phi_ce_opt", "rad", 1.2, "CE optimum angle", _T1),
        _decade("Mmax", "N*m", 52.0, "maximal isometric CE moment", _T1),
        _decade("a_rel", "1", 0.21, "Hill constant", _T1),
        _decade("b_rel", "1/s", 1.55, "Hill constant", _T1),
        _decade("w", "1", 0.56, "width of the moment-angle parabola", _T1),
        Param("k_pee", "N*m/rad^2", 0.0, 0.0, 3770.0, "PEE stiffness (0 in the paper)", _T1),
        Param("phi_pee0_rel", "1", 1.0, 0.5, 2.0, "PEE slack angle / phi_ce_opt", _T1),
    )
    reads = (Port("act", "1", "act.A"), Port("xi_exc", "1", None, "xi_sink"))
    exposes = {"M": "N*m", "omega_ce": "rad/s", "F0": "N*m", "e_test": "rad", "phi_mtc_offset": "rad"}
    states = (State("phi_ce", "rad", 1e-3),)

    def __init__(self, subject: str | int = "3", **overrides: float) -> None:
        from .hatze_parameters import load_subject

        sub = load_subject(subject)
        table = {"k_see": sub.k_see, "phi_ce_opt": sub.phi_ce_opt, "Mmax": sub.m_max, "a_rel": sub.a_rel,
                 "b_rel": sub.b_rel, "w": sub.w, "k_pee": sub.k_pee, "phi_pee0_rel": sub.phi_pee0_rel}
        super().__init__(**{**{k: float(v) for k, v in table.items()}, **overrides})
        self.subject = str(subject)


def hatze_excitation(theta: Any = None, **overrides: float) -> dict[str, Component]:
    """Hatze's excitation as slot {"act": HatzeExcitation}: it takes the place of Modules 1-2."""
    return {"act": HatzeExcitation(theta, **overrides)}


def hatze_contraction(subject: str | int = "3", **overrides: float) -> dict[str, Component]:
    """Hatze's angular MTC as slot {"force": HatzeMTC} (output M in N m)."""
    return {"force": HatzeMTC(subject, **overrides)}


COMPONENTS: tuple[type[Component], ...] = (HatzeExcitation, HatzeTrend, HatzeMTC)


