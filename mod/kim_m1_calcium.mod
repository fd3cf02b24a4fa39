COMMENT
Module 1 of Kim, Sandercock & Heckman 2015 (seed 001): spikes -> Ca2+ in the SR and sarcoplasm.

Equations (spec/kim2015_model.md): eqs 1-7, cooperativity K6 = K6i/(1 + 5 Atil), length compensation eq 18
(K5 = phi(Xm) K5i when lencomp = 1).
Units: time ms, concentration M, rates K1,K3,K5i (/M/ms), K2,K4,K6i,Rmax (/ms), K (/M), Umax (M/ms), tau1,tau2 ms.

Release (eq 3) uses two recursive kernels, S2 = sum exp(-(t-ti)/tau2) and S12 = sum exp(-(t-ti)(1/tau1+1/tau2)),
both jumping by 1 at each spike (NET_RECEIVE), so R = [CaSR] Rmax (S2 - S12) costs the same whatever the spike count.

Coupling (documented interface, see neuromuscle/model/kim.py):
  POINTER atil  -> activation state Atil of the activation mechanism (KimAct), dimensionless
  POINTER xm    -> muscle length Xm (mm) held by a MuscleLength point process
  POINTER release_gain, uptake_gain -> modulation ports (1): R is multiplied by release_gain and the pump U by
                   uptake_gain.  An extension points them at its own RANGE output; they are read only when
                   use_ports = 1 (the Python wiring sets it when an extension is attached, and points unused
                   ones at this mechanism's RANGE unity = 1); with use_ports = 0 (default) they count as 1 and
                   need not be set.  x*1 is exact: off is bit-identical.
Exposes RANGE CaSPT (M), and the parameters shared with Module 2 (T0 (M), phi1, phi2 (eq 18), xopt (mm)), which
KimAct reads through POINTERs: they live in this mechanism only.
Spikes: NET_RECEIVE with weight w (1 for one spike): both release kernels jump by w.

Numerics.  Fixed step: one linearly implicit (Rosenbrock-Euler) step of the five coupled Ca states with the
exact analytic Jacobian, solved by eliminating CaSRCS, CaSPB and CaSPT into a 2x2 system; the kernels decay
exactly and R uses their exact average over the step.  K6's cooperativity reads Atil extrapolated to the step's
middle from its last two values (KimAct advances after this mechanism): with Atil of the step's start the loop
CaSPT -> Atil -> K6 lagged by a step, and a regenerative twitch was missed (sweep draw 524: 1.6 N instead of 6.1 N).  L-stable, no Newton iteration, no history loop.
Variable step (CVODE): the DERIVATIVE block gives the exact right-hand side, written a - b*y so that CVODE's
diagonal Jacobian approximation sees the stiff terms.  The state equations are written as y' = a - b*y: in
fixed step a holds the step's increment / dt and b = 0, so METHOD euler applies exactly that increment.
ENDCOMMENT

NEURON {
    POINT_PROCESS KimCa
    THREADSAFE
    RANGE K1, K2, K3, K4, K5i, K6i, K, Rmax, Umax, tau1, tau2, CS0, B0, T0, CaSR0
    RANGE phi1, phi2, phi3, phi4, xopt, lencomp
    RANGE R, U, K5, K6, phi, nspike, unity, use_ports, rest
    POINTER atil, xm, release_gain, uptake_gain
}

UNITS {
    (M) = (1/liter)
}

PARAMETER {
    K1 = 3000 (/M/ms)
    K2 = 3 (/ms)
    K3 = 400 (/M/ms)
    K4 = 1 (/ms)
    K5i = 4e5 (/M/ms)
    K6i = 150 (/ms)
    K = 850 (/M)
    Rmax = 10 (/ms)
    Umax = 2000 (M/ms)
    tau1 = 3 (ms)
    tau2 = 25 (ms)
    CS0 = 0.03 (M)
    B0 = 0.00043 (M)
    T0 = 0.00007 (M)
    CaSR0 = 0.0025 (M)
    phi1 = 0.03 (/mm)
    phi2 = 1.23 (1)
    phi3 = 0.01 (/mm)
    phi4 = 1.08 (1)
    xopt = -8 (mm)
    lencomp = 1 (1)
    unity = 1 (1)
    use_ports = 0 (1)
    rest = 1 (1)
}

ASSIGNED {
    atilp (1)
    fresh (1)
    atx (1)
    dt (ms)
    atil (1)
    xm (mm)
    release_gain (1)
    uptake_gain (1)
    R (M/ms)
    U (M/ms)
    K5 (/M/ms)
    K6 (/ms)
    phi (1)
    nspike (1)
    a1 (M/ms) a2 (M/ms) a3 (M/ms) a4 (M/ms) a5 (M/ms) a6 (/ms) a7 (/ms)
    b1 (/ms) b2 (/ms) b3 (/ms) b4 (/ms) b5 (/ms) b6 (/ms) b7 (/ms)
    rg (1)
    ug (1)
    hc (ms)
    e2c (1)
    e12c (1)
    g2c (1)
    g12c (1)
}

STATE {
    CaSR (M)
    CaSRCS (M)
    CaSP (M)
    CaSPB (M)
    CaSPT (M)
    S2 (1)
    S12 (1)
}

INITIAL {
    LOCAL bq
    if (rest) {
        : the resting steady state: no release, so the pump has returned every ion to the SR (CaSP = CaSPB =
        : CaSPT = 0) and the SR's calcium CaSR0 is shared between free CaSR and calsequestrin (eq 2 at rest:
        : K1 CaSR (CS0 - CaSRCS) = K2 CaSRCS, CaSR + CaSRCS = CaSR0), the positive root of a quadratic
        bq = K1*(CS0 - CaSR0) + K2
        UNITSOFF
        CaSR = 2*K2*CaSR0/(bq + sqrt(bq*bq + 4*K1*K2*CaSR0))
        UNITSON
        CaSRCS = CaSR0 - CaSR
    } else {
        : the published initial state (seed 001): all SR calcium free; it settles within ~100 ms
        CaSR = CaSR0
        CaSRCS = 0
    }
    CaSP = 0
    CaSPB = 0
    CaSPT = 0
    S2 = 0
    S12 = 0
    nspike = 0
    hc = -1
    fresh = 1
    atx = atil
    rates_coeffs()
}

BREAKPOINT {
    SOLVE states METHOD euler
}

DERIVATIVE states {
    if (cvode_on()) {
        exact_rhs()
    } else {
        implicit_step(dt)
    }
    CaSR' = a1 - b1*CaSR
    CaSRCS' = a2 - b2*CaSRCS
    CaSP' = a3 - b3*CaSP
    CaSPB' = a4 - b4*CaSPB
    CaSPT' = a5 - b5*CaSPT
    S2' = a6 - b6*S2
    S12' = a7 - b7*S12
}

PROCEDURE rates_coeffs() {
    : atx: the Atil that K6 uses (set by the caller)
    : K5, K6 and the length factor phi from the current Atil and Xm (eq 18 and the cooperativity);
    : each POINTER is read once (a NEURON 9 pointer dereference is not free)
    LOCAL x
    x = xm
    if (x <= xopt) {
        phi = phi1*x + phi2
    } else {
        phi = phi3*x + phi4
    }
    if (lencomp) {
        K5 = K5i*phi
    } else {
        K5 = K5i
    }
    K6 = K6i/(1 + 5*atx)
    : modulation ports, read only when an extension drives them (use_ports = 1, set by the Python wiring);
    : otherwise the neutral 1, with no pointer dereference per step (and nothing to set for a hoc user)
    if (use_ports) {
        rg = release_gain
        ug = uptake_gain
    } else {
        rg = 1
        ug = 1
    }
}

FUNCTION pump(c (M)) (M/ms) {
    : eq 4; zero for negative concentration
    LOCAL z, w
    if (c <= 0) {
        pump = 0
    } else {
        z = c*c*K*K
        w = z/(1 + c*K + z)
        pump = Umax*w*w
    }
}

FUNCTION dpump(c (M)) (/ms) {
    : d(eq 4)/d[CaSP]
    LOCAL z, D, w
    if (c <= 0) {
        dpump = 0
    } else {
        z = c*c*K*K
        D = 1 + c*K + z
        w = z/D
        dpump = 2*Umax*w*(2*K*K*c + K*K*K*c*c)/(D*D)
    }
}

PROCEDURE exact_rhs() {
    LOCAL r, tau12, up
    atx = atil
    rates_coeffs()
    tau12 = 1/(1/tau1 + 1/tau2)
    r = rg*Rmax*(S2 - S12)
    R = CaSR*r
    U = ug*pump(CaSP)
    : eq 1, linear in CaSR
    b1 = K1*(CS0 - CaSRCS) + r
    a1 = K2*CaSRCS + U
    : eq 2, linear in CaSRCS
    b2 = K1*CaSR + K2
    a2 = K1*CaSR*CS0
    : eq 5: every term but the pump is linear in CaSP; the pump is split into its tangent at CaSP, so that
    : -U = -(U - up CaSP) - up CaSP with up = dU/d[CaSP] on the diagonal (b3) and the rest in a3: the same
    : right-hand side, and CVODE's diagonal Jacobian now holds the pump's rate.  With the pump wholly in a3, a
    : fast pump (Umax, K large: U/[CaSP] ~ 700 /ms) was invisible to CVODE's Newton iteration and forced steps
    : of ~0.3 us through every tetanus (sweep draws 148, 385, 494, 736, 756, 882, 984: budget stops).
    up = ug*dpump(CaSP)
    b3 = K5*(T0 - CaSPT) + K3*(B0 - CaSPB) + up
    a3 = K6*CaSPT + K4*CaSPB + R - U + up*CaSP
    : eq 6
    b4 = K3*CaSP + K4
    a4 = K3*CaSP*B0
    : eq 7
    b5 = K5*CaSP + K6
    a5 = K5*CaSP*T0
    : release kernels
    a6 = 0
    b6 = 1/tau2
    a7 = 0
    b7 = 1/tau12
}

PROCEDURE implicit_step(h (ms)) {
    LOCAL tau12, e2, e12, r, y1, y3, f1, f2, f3, f4, f5, J11, J12, J13, J21, J22, J31, J33, J34, J35, J43, J44, J53, J55, d2, d4, d5, m11, m13, m31, m33, c1, c3, det, D1, D2, D3, D4, D5, Up, a0
    : Atil at the step's middle, extrapolated from its last two values (KimAct advances after this mechanism):
    : K6's cooperativity then lags by O(dt^2), not O(dt)
    a0 = atil
    if (fresh) {
        : the run's first step: no previous value (INITIAL ran before KimAct set Atil)
        atilp = a0
        fresh = 0
    }
    atx = a0 + 0.5*(a0 - atilp)
    if (atx < 0) {
        atx = 0
    }
    atilp = a0
    rates_coeffs()
    if (h != hc) {
        : kernel decay and step-mean factors depend only on the step: computed once per dt
        tau12 = 1/(1/tau1 + 1/tau2)
        e2c = exp(-h/tau2)
        e12c = exp(-h/tau12)
        g2c = tau2*(1 - e2c)/h
        g12c = tau12*(1 - e12c)/h
        hc = h
    }
    e2 = e2c
    e12 = e12c
    : exact mean of Rmax (S2 - S12) over the step
    r = rg*Rmax*(S2*g2c - S12*g12c)
    y1 = CaSR
    y3 = CaSP
    R = y1*r
    U = ug*pump(y3)
    Up = ug*dpump(y3)
    f1 = -K1*y1*(CS0 - CaSRCS) + K2*CaSRCS - R + U
    f2 = K1*y1*(CS0 - CaSRCS) - K2*CaSRCS
    f3 = -K5*y3*(T0 - CaSPT) + K6*CaSPT - K3*y3*(B0 - CaSPB) + K4*CaSPB + R - U
    f4 = K3*y3*(B0 - CaSPB) - K4*CaSPB
    f5 = K5*y3*(T0 - CaSPT) - K6*CaSPT
    J11 = -K1*(CS0 - CaSRCS) - r
    J12 = K1*y1 + K2
    J13 = Up
    J21 = K1*(CS0 - CaSRCS)
    J22 = -K1*y1 - K2
    J31 = r
    J33 = -K5*(T0 - CaSPT) - K3*(B0 - CaSPB) - Up
    J34 = K3*y3 + K4
    J35 = K5*y3 + K6
    J43 = K3*(B0 - CaSPB)
    J44 = -K3*y3 - K4
    J53 = K5*(T0 - CaSPT)
    J55 = -K5*y3 - K6
    : (I - hJ) D = h f; rows 2, 4, 5 give D2, D4, D5 in terms of D1, D3
    d2 = 1 - h*J22
    d4 = 1 - h*J44
    d5 = 1 - h*J55
    m11 = 1 - h*J11 - h*J12*h*J21/d2
    m13 = -h*J13
    c1 = h*f1 + h*J12*h*f2/d2
    m31 = -h*J31
    m33 = 1 - h*J33 - h*J34*h*J43/d4 - h*J35*h*J53/d5
    c3 = h*f3 + h*J34*h*f4/d4 + h*J35*h*f5/d5
    det = m11*m33 - m13*m31
    D1 = (c1*m33 - m13*c3)/det
    D3 = (m11*c3 - m31*c1)/det
    D2 = (h*f2 + h*J21*D1)/d2
    D4 = (h*f4 + h*J43*D3)/d4
    D5 = (h*f5 + h*J53*D3)/d5
    a1 = D1/h
    a2 = D2/h
    a3 = D3/h
    a4 = D4/h
    a5 = D5/h
    a6 = S2*(e2 - 1)/h
    a7 = S12*(e12 - 1)/h
    if (S12 < 1e-200) {
        : a silent unit's kernels decay towards subnormal numbers, whose arithmetic is ~100x slower:
        : flush them (below 1e-200 they change nothing)
        a7 = -S12/h
        if (S2 < 1e-200) {
            a6 = -S2/h
        }
    }
    b1 = 0
    b2 = 0
    b3 = 0
    b4 = 0
    b5 = 0
    b6 = 0
    b7 = 0
}

INCLUDE "cvode_on.inc"

NET_RECEIVE(w (1)) {
    : a spike of weight w (1 for one spike): both release kernels jump by w (eq 3 written recursively)
    S2 = S2 + w
    S12 = S12 + w
    nspike = nspike + 1
}
