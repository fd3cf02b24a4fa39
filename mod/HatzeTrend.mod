TITLE Hatze's first-order trend model of the free calcium (van Zandwijk et al. 1998)

COMMENT
Hatze's first-order trend model of the free calcium (van Zandwijk et al. 1998, eq 10; docs/reference/hatze.md), an excitation model
driven by a stimulation rate instead of individual spikes:
    dgamma/dt_s = m (c nu - gamma),   nu = stimulation rate / 100 Hz   (t_s in seconds; NEURON's t is ms)
    A = q(gamma, xi) of eq 9 with theta5 (same form as HatzeExc)
Units: m 1/s; c in gamma's raw scale (s^4, the convention of neuromuscle.hatze: Table 3's c in mol/L differs by a
constant); gamma s^4; theta5 1/s^4; nu 1 (RANGE: set, or Vector.play a rate profile / 100 Hz).
Exposes A for KimForce/HatzeMTC (POINTER act), like KimAct and HatzeExc.
Numerics: linear in gamma, so METHOD cnexp is exact for nu constant over a step; CVODE uses the same block.
ENDCOMMENT

NEURON {
    POINT_PROCESS HatzeTrend
    THREADSAFE
    RANGE m, c, nu, theta5, q0, rho2, xicheck, s, xi, A
}

PARAMETER {
    m = 7.94 (/s)
    c = 3.91e-14 (s4)
    nu = 0 (1)
    theta5 = 4.57e14 (/s4)
    q0 = 0.005 (1)
    rho2 = 1.05 (1)
    xicheck = 2.90 (1)
    s = 1.0 (1)
    xi = 1.0 (1)
}

ASSIGNED {
    A (1)
}

STATE {
    g (s4)
}

INITIAL {
    g = 0
    active_state()
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    g' = m*(c*nu - g)/(1000)
    active_state()
}

INCLUDE "hatze_active_state.inc"
