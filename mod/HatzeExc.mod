TITLE Hatze's excitation dynamics (van Zandwijk, Bobbert, Harlaar & Hof 1998; Hatze 1977)

COMMENT
Hatze's excitation dynamics (van Zandwijk, Bobbert, Harlaar & Hof 1998, Appendix eqs 6-9; docs/reference/hatze.md): an excitation model that can take
the place of Modules 1-2 (KimCa + KimAct) in front of Module 3 (KimForce reads A through POINTER act).

Equations, with time t_s in SECONDS as in the seed (NEURON's t is in ms: t_s = t/1000):
    beta''  + theta1 beta'  + theta2 beta  = alpha(t)        (eq 6)   beta in s^2
    gamma'' + theta3 gamma' + theta4 gamma = beta(t)         (eq 7)   gamma in s^4
    alpha(t) = sin(pi (t - t0)/1 ms) during 1 ms after each stimulus t0 (a NET_RECEIVE event), else 0 (eq 8)
    A = q = 1 - (1 - q0)/(m1 - m2) (m1 exp(m2 x) - m2 exp(m1 x)),  x = rho*(xi) theta5 gamma,
        m1,2 = -rho2 +/- sqrt(rho2^2 - 1),  rho*(xi) = (xicheck^s - 1)/((xicheck/xi)^s - 1)      (eq 9)
Units: theta1, theta3 1/s; theta2, theta4 1/s^2; theta5 1/s^4; vb = dbeta/dt_s (s), vg = dgamma/dt_s (s^3);
xi = CE length / optimum (1).  Pulses may not overlap: a stimulus within 1 ms of the previous one is counted in
noverlap and ignored (the caller refuses such trains before running).

Numerics.  Fixed step: the linear system is advanced by the trapezoidal rule (second order, A-stable) with the
exact half-sine at the step's midpoint, the two 2x2 blocks solved in closed form (gamma's block driven by the
trapezoidal mean of beta); the step's increments reach the states through METHOD euler (no STATE is assigned
inside DERIVATIVE).  CVODE: the DERIVATIVE block gives the exact right-hand side (a - b*y form, see
KimCa); pulse starts and ends are events.
ENDCOMMENT

NEURON {
    POINT_PROCESS HatzeExc
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
    RANGE theta1, theta2, theta3, theta4, theta5, q0, rho2, xicheck, s, xi
    RANGE A, alpha, noverlap, tstep
}

PARAMETER {
    theta1 = 3.50e5 (/s)
    theta2 = 5.58e6 (/s2)
    theta3 = 1.85e4 (/s)
    theta4 = 2.92e5 (/s2)
    theta5 = 4.57e14 (/s4)
    q0 = 0.005 (1)
    rho2 = 1.05 (1)
    xicheck = 2.90 (1)
    s = 1.0 (1)
    xi = 1.0 (1)
    variable_step = 0 (1)
}

ASSIGNED {
    dt (ms)
    tstep (ms)
    A (1)
    alpha (1)
    on (1)
    t0 (ms)
    noverlap (1)
    ab (s2/ms)
    ag (s4/ms)
    a2 (s/ms)
    a4 (s3/ms)
    c2 (/ms)
    c4 (/ms)
}

STATE {
    b (s2)
    vb (s)
    g (s4)
    vg (s3)
}

INITIAL {
    b = 0
    vb = 0
    g = 0
    vg = 0
    on = 0
    alpha = 0
    noverlap = 0
    active_state()
    tstep = t
}

BREAKPOINT {
    SOLVE states METHOD euler
}

DERIVATIVE states {
    LOCAL nst
    if (variable_step) {
        alpha = drive(t)
        ab = vb/(1000)
        a2 = (alpha - theta2*b)/(1000)
        c2 = theta1/(1000)
        ag = vg/(1000)
        a4 = (b - theta4*g)/(1000)
        c4 = theta3/(1000)
    } else {
        : the whole step (dt is halved in this block under secondorder: fixed_step.inc)
        nst = euler_steps(t, tstep, dt)
        trapezoid_step(dt*nst)
        c2 = 0
        c4 = 0
    }
    tstep = t
    b' = ab
    vb' = a2 - c2*vb
    g' = ag
    vg' = a4 - c4*vg
    active_state()
}

FUNCTION drive(tt (ms)) {
    : eq 8: the half-sine of the current pulse (dimensionless)
    if (on && tt >= t0 && tt < t0 + 1) {
        drive = sin(3.141592653589793*(tt - t0)/(1 (ms)))
    } else {
        drive = 0
    }
}

PROCEDURE trapezoid_step(h (ms)) {
    : trapezoidal rule for z' = M z + input on the two 2x2 blocks, in the paper's seconds (hs = h in s).  The
    : new values are handed to METHOD euler as increments per ms (ab, a2, ag, a4): no state is assigned here.
    LOCAL hs, k, u, r1, r2, det, bn, vbn, gn, vgn, bm
    hs = (0.001)*h
    k = hs/2
    alpha = drive(t + h/2)
    : beta block: b' = vb, vb' = alpha - theta1 vb - theta2 b (per s)
    u = alpha
    r1 = b + k*vb
    r2 = vb - k*(theta2*b + theta1*vb) + hs*u
    det = 1 + k*theta1 + k*k*theta2
    bn = (r1*(1 + k*theta1) + k*r2)/det
    vbn = (r2 - k*theta2*r1)/det
    : gamma block driven by the trapezoidal mean of beta
    bm = (b + bn)/2
    u = bm
    r1 = g + k*vg
    r2 = vg - k*(theta4*g + theta3*vg) + hs*u
    det = 1 + k*theta3 + k*k*theta4
    gn = (r1*(1 + k*theta3) + k*r2)/det
    vgn = (r2 - k*theta4*r1)/det
    ab = (bn - b)/h
    a2 = (vbn - vb)/h
    ag = (gn - g)/h
    a4 = (vgn - vg)/h
}

INCLUDE "hatze_active_state.inc"
INCLUDE "fixed_step.inc"

NET_RECEIVE(w) {
    if (flag == 0) {
        if (on) {
            noverlap = noverlap + 1
        } else {
            on = 1
            t0 = t
            net_send(1, 1)
        }
    } else if (flag == 1) {
        on = 0
    }
}
