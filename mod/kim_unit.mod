COMMENT
Kim, Sandercock & Heckman 2015 (seed 001) Modules 1-3 in one mechanism: spikes -> Ca2+ -> activation -> force.

The same equations and the same arithmetic as KimCa (kim_m1_calcium.mod, eqs 1-7, 18), KimAct
(kim_m2_activation.mod, eq 8, 19-20) and KimForce (kim_m3_force.mod, eqs 9-12), copied statement for statement, so
that the fixed step gives the three mechanisms' numbers bit for bit (tests/model/test_fused.py) and CVODE sees the
same right-hand side and the same diagonal Jacobian.  What is gone is the overhead around the arithmetic
(docs/speed.md): no POINTERs between the modules (one read of the length per step), one per-instance loop instead
of three, no Jacobian loops, the shared parameters read directly.  Read the three files' headers for the
equations, units and numerics; only what differs is written here.

Coupling: POINTER xm, vm -> muscle length (mm) and velocity (mm/s) of a MuscleLength point process (one per rank
in a pool).  No modulation ports: model extensions need the three mechanisms (the Python wiring refuses them).
Spikes: NET_RECEIVE with weight w, as KimCa.

The fixed step's split at eq 20's switch and the CE's error-controlled substeps (KimAct's switch_in_step,
KimForce's ce_step, check_step, split_step) are copied likewise; the CE state is dxce = XCE - x0 as in KimForce.

Order within a step, as NEURON runs the three mechanisms (KimCa, KimAct, KimForce are registered in that order):
Module 1 with the previous step's Atil, Module 2 with the new [CaSPT], Module 3 with the new A.

Fixed step: the states are assigned directly in the DERIVATIVE block (the same expressions the three mechanisms'
generated code evaluates: y + h (D/h) for Modules 1 and 3, the cnexp update for Atil), and every derivative is
then zero, so METHOD euler adds exactly nothing.  CVODE: the DERIVATIVE block gives the three right-hand sides.

Slower muscle (substeps = k >= 1, fixed step only): the muscle advances once every k membrane steps, by one step
of k dt at the end of those k (spikes arriving in between act at the next muscle step; the outputs hold between
muscle steps).  k = 1 is the three-mechanism update.  The movement clock (eq 19-20) is read at the muscle step's
midpoint, as KimAct reads it at the fixed step's.
ENDCOMMENT

NEURON {
    POINT_PROCESS KimUnit
    THREADSAFE
    : Module 1
    RANGE K1, K2, K3, K4, K5i, K6i, K, Rmax, Umax, tau1, tau2, CS0, B0, T0, CaSR0
    RANGE phi1, phi2, phi3, phi4, xopt, lencomp
    RANGE R, U, K5, K6, phi, nspike
    : Module 2
    RANGE C1, C2, C3, C4, C5, alpha, alpha1, alpha2, alpha3, beta, gamma
    RANGE movdep, lengdiv, onset, Afloor, atil0
    RANGE A, alpha_t, Ainf, tauA, asw, ssw
    : Module 3
    RANGE P0, KSE, g1, g2, a0, b0, c0, d0, vmax, asym, lincurv, fcmin, F0, subtol, nsubmax
    RANGE F, Fse, Fc, vce, nasym, xce, x0, nsub, nsplit
    : the unit
    RANGE rest, substeps
    : intermediates set and used within one instance's evaluation: per-thread GLOBALs, not per-instance fields
    : (fewer fields: nocmodl's field accessors stay inlined, see docs/speed.md)
    GLOBAL a1, a2, a3, a4, a5, a6, a7, b1, b2, b3, b4, b5, b6, b7, kA, kAd, dvdF, aa, bb, dfdx, kse, al, xl
    POINTER xm, vm
}

UNITS {
    (M) = (1/liter)
    (mV) = (millivolt)
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
    C1 = 0.128 (1)
    C2 = 0.093 (1)
    C3 = 61.206 (ms)
    C4 = -13.116 (1)
    C5 = 5.095 (1)
    alpha = 2 (1)
    alpha1 = 4.77 (1)
    alpha2 = 400 (ms)
    alpha3 = 160 (ms)
    beta = 0.47 (1)
    gamma = 0.001 (s/mm)
    movdep = 0 (1)
    lengdiv = 0 (1)
    onset = 1e9 (ms)
    Afloor = 0.001 (1)
    atil0 = 0 (1)
    P0 = 23 (N)
    KSE = 0.4 (/mm)
    g1 = -8 (mm)
    g2 = 21.4 (mm)
    a0 = 2.35 (N)
    b0 = 24.35 (mm/s)
    c0 = -7.4 (N)
    d0 = 30.3 (mm/s)
    vmax = 1e5 (mm/s)
    asym = 0.95 (1)
    lincurv = 0.02 (1)
    fcmin = 1e-4 (1)
    subtol = 1e-3 (1)
    nsubmax = 64 (1)
    F0 = 0 (N)
    rest = 1 (1)
    substeps = 1 (1)
}

ASSIGNED {
    xce (mm)
    x0 (mm)
    xlp (mm)
    alp (1)
    xmp (mm)
    mvp (1)
    vmp (mm/s)
    ab (1)
    asw (1)
    ssw (1)
    sw (1)
    acs (mm/ms)
    nsub (1)
    nsplit (1)
    atilp (1)
    atx (1)
    fresh (1)
    v (mV)      : declared for modlunit, which asks it of a point process with GLOBALs; not used
    dt (ms)
    xm (mm)
    vm (mm/s)
    xl (mm)
    : Module 1
    R (M/ms)
    U (M/ms)
    K5 (/M/ms)
    K6 (/ms)
    phi (1)
    nspike (1)
    a1 (M/ms) a2 (M/ms) a3 (M/ms) a4 (M/ms) a5 (M/ms) a6 (/ms) a7 (/ms)
    b1 (/ms) b2 (/ms) b3 (/ms) b4 (/ms) b5 (/ms) b6 (/ms) b7 (/ms)
    hc (ms)
    e2c (1)
    e12c (1)
    g2c (1)
    g12c (1)
    : Module 2
    A (1)
    alpha_t (1)
    Ainf (1)
    tauA (ms)
    kA (/ms)
    kAd (/ms)
    : Module 3
    F (N)
    Fse (N)
    Fc (N)
    vce (mm/s)
    dvdF (mm/s/N)
    nasym (1)
    aa (mm/ms)
    bb (/ms)
    dfdx (/ms)
    kse (N/mm)
    xmc (mm)
    gc (1)
    al (1)
    : the substep counter
    kcount (1)
    zeroed (1)
}

STATE {
    CaSR (M)
    CaSRCS (M)
    CaSP (M)
    CaSPB (M)
    CaSPT (M)
    S2 (1)
    S12 (1)
    atil (1)
    dxce (mm)
}

INITIAL {
    LOCAL bq
    xl = xm
    : Module 1 (KimCa's INITIAL; its rates_coeffs() there sets nothing a step reads before recomputing it)
    if (rest) {
        bq = K1*(CS0 - CaSR0) + K2
        UNITSOFF
        CaSR = 2*K2*CaSR0/(bq + sqrt(bq*bq + 4*K1*K2*CaSR0))
        UNITSON
        CaSRCS = CaSR0 - CaSR
    } else {
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
    kcount = 0
    zeroed = 0
    rates_coeffs()
    : Module 2 (KimAct's INITIAL)
    if (rest) {
        rates()
        atil = Ainf
    } else {
        atil = atil0
    }
    activation(t, 0)
    xmp = xl
    vmp = vm
    ssw = 0
    asw = A
    mvp = t >= onset
    : Module 3 (KimForce's INITIAL)
    al = A
    xmc = 1e9
    x0 = xl
    dxce = 0
    xce = x0
    se_force()
    if (rest) {
        dxce = -Fc/(P0*KSE)
    } else {
        dxce = -F0/(P0*KSE)
    }
    xce = x0 + dxce
    nasym = 0
    nsub = 0
    nsplit = 0
    xlp = xl
    alp = al
    se_force()
}

BREAKPOINT {
    SOLVE states METHOD euler
}

DERIVATIVE states {
    : the length is read once per evaluation (under the fixed step, once per update: the POINTER read is a
    : generic data handle in NEURON 9, 3 % of a pool's time when done every step)
    if (cvode_on()) {
        xl = xm
        rhs_all()
    } else {
        kcount = kcount + 1
        if (kcount >= substeps) {
            kcount = 0
            xl = xm
            step_all(substeps*dt)
        }
        if (zeroed == 0) {
            : the states are already advanced: nothing is left for METHOD euler to add (set once per run;
            : rhs_all, under CVODE, sets them again)
            a1 = 0  a2 = 0  a3 = 0  a4 = 0  a5 = 0  a6 = 0  a7 = 0
            b1 = 0  b2 = 0  b3 = 0  b4 = 0  b5 = 0  b6 = 0  b7 = 0
            kAd = 0
            aa = 0
            bb = 0
            zeroed = 1
        }
    }
    CaSR' = a1 - b1*CaSR
    CaSRCS' = a2 - b2*CaSRCS
    CaSP' = a3 - b3*CaSP
    CaSPB' = a4 - b4*CaSPB
    CaSPT' = a5 - b5*CaSPT
    S2' = a6 - b6*S2
    S12' = a7 - b7*S12
    atil' = (Ainf - atil)*kAd
    dxce' = aa - bb*dxce
    if (cvode_on()) {
        : KimForce's DERIVATIVE ends with se_force() (its CVODE output F)
        se_force()
    }
}

PROCEDURE rhs_all() {
    : CVODE: KimCa's, KimAct's and KimForce's DERIVATIVE blocks in registration order
    zeroed = 0
    xce = x0 + dxce
    exact_rhs()
    rates()
    kAd = kA
    activation(t, 1)
    al = A
    se_force()
    velocity()
    kse = P0*KSE
    if (xl - xce > 0 || (xl - xce == 0 && vce < 0)) {
        dfdx = -kse*dvdF/(1000)
    } else {
        dfdx = 0
    }
    bb = -dfdx
    aa = vce/(1000) + bb*dxce
}

PROCEDURE step_all(h (ms)) {
    : one fixed step of length h of the three modules, states assigned here (h = dt: the three mechanisms'
    : expressions exactly)
    LOCAL mvn
    : Module 1
    implicit_step(h)
    : Module 2: KimAct's cnexp update as nocmodl writes it, then eq 19-20 at the step's midpoint
    rates()
    atil = atil + (1 - exp(h*(-kA)))*(-(Ainf*kA)/(-kA) - atil)
    activation(t - 0.5*h, 0)
    mvn = t - 0.5*h >= onset
    switch_in_step(mvn)
    if (mvn && !mvp && ssw == 0 && (movdep || lengdiv)) {
        : KimAct's: the movement onset in this step (A jumped): hold A over the CE substeps
        ssw = -1
    }
    mvp = mvn
    xmp = xl
    vmp = vm
    : Module 3: KimForce's DERIVATIVE block (fixed-step branch), then its BREAKPOINT's report at the step's end
    al = A
    se_force()
    velocity()
    kse = P0*KSE
    sw = ssw
    if (sw > 0 && sw < 1) {
        split_step(h)
    } else {
        ce_step(h)
        if (nsubmax > 1 && Fc > 0) {
            if (sw < 0) {
                check_step(h, xlp, al)
            } else {
                check_step(h, xlp, alp)
            }
        }
    }
    dxce = dxce + h*acs
    xce = x0 + dxce
    se_force()
    velocity()
    xlp = xl
    alp = al
}

: ---- Module 1 (kim_m1_calcium.mod) ----

PROCEDURE rates_coeffs() {
    LOCAL x
    x = xl
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
}

FUNCTION pump(c (M)) (M/ms) {
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
    : KimCa's CVODE right-hand side with the pump's tangent on the diagonal (rg = ug = 1: no ports)
    LOCAL r, tau12, up
    atx = atil
    rates_coeffs()
    tau12 = 1/(1/tau1 + 1/tau2)
    r = 1*Rmax*(S2 - S12)
    R = CaSR*r
    U = 1*pump(CaSP)
    b1 = K1*(CS0 - CaSRCS) + r
    a1 = K2*CaSRCS + U
    b2 = K1*CaSR + K2
    a2 = K1*CaSR*CS0
    up = 1*dpump(CaSP)
    b3 = K5*(T0 - CaSPT) + K3*(B0 - CaSPB) + up
    a3 = K6*CaSPT + K4*CaSPB + R - U + up*CaSP
    b4 = K3*CaSP + K4
    a4 = K3*CaSP*B0
    b5 = K5*CaSP + K6
    a5 = K5*CaSP*T0
    a6 = 0
    b6 = 1/tau2
    a7 = 0
    b7 = 1/tau12
}

PROCEDURE implicit_step(h (ms)) {
    : KimCa's linearly implicit step (rg = ug = 1), applied to the states (intermediates are LOCALs: no stores)
    LOCAL k6, k7, tau12, e2, e12, r, y1, y3, f1, f2, f3, f4, f5, J11, J12, J13, J21, J22, J31, J33, J34, J35, J43, J44, J53, J55, d2, d4, d5, m11, m13, m31, m33, c1, c3, det, D1, D2, D3, D4, D5, Up
    : K6 reads Atil extrapolated to the step's middle (as KimCa: Atil here is still the step's start value)
    if (fresh) {
        atilp = atil
        fresh = 0
    }
    atx = atil + 0.5*(atil - atilp)
    if (atx < 0) {
        atx = 0
    }
    atilp = atil
    rates_coeffs()
    if (h != hc) {
        tau12 = 1/(1/tau1 + 1/tau2)
        e2c = exp(-h/tau2)
        e12c = exp(-h/tau12)
        g2c = tau2*(1 - e2c)/h
        g12c = tau12*(1 - e12c)/h
        hc = h
    }
    e2 = e2c
    e12 = e12c
    r = 1*Rmax*(S2*g2c - S12*g12c)
    y1 = CaSR
    y3 = CaSP
    R = y1*r
    U = 1*pump(y3)
    Up = 1*dpump(y3)
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
    : KimCa's y + dt (a - 0 y) with a = D/h (h = dt): the same roundings
    CaSR = CaSR + h*(D1/h)
    CaSRCS = CaSRCS + h*(D2/h)
    CaSP = CaSP + h*(D3/h)
    CaSPB = CaSPB + h*(D4/h)
    CaSPT = CaSPT + h*(D5/h)
    k6 = S2*(e2 - 1)/h
    k7 = S12*(e12 - 1)/h
    if (S12 < 1e-200) {
        k7 = -S12/h
        if (S2 < 1e-200) {
            k6 = -S2/h
        }
    }
    S2 = S2 + h*k6
    S12 = S12 + h*k7
}

: ---- Module 2 (kim_m2_activation.mod) ----

PROCEDURE rates() {
    LOCAL x, ev
    x = CaSPT/T0
    Ainf = 1/(1 + exp(-2*(x - C1)/C2))
    ev = exp((x - C4)/(2*C5))
    kA = 0.5*(ev + 1/ev)/C3
    tauA = 1/kA
}

PROCEDURE activation(tc (ms), strict (1)) {
    : KimAct's activation(), A and alpha_t computed in LOCALs and stored once (the same arithmetic)
    LOCAL at, dv, mv, vl, a, alt, md, ld
    UNITSOFF
    if (strict) {
        mv = tc > onset
    } else {
        mv = tc >= onset
    }
    md = movdep && mv
    ld = lengdiv && mv
    at = atil
    if (at < 0) {
        at = 0
    }
    if (md) {
        alt = alpha + alpha1*(1 + tanh((t - onset - alpha2)/alpha3))
    } else {
        alt = alpha
    }
    if (alt == 2) {
        a = at*at
    } else {
        a = pow(at, alt)
    }
    ab = a
    if (ld) {
        vl = vm
        if (xl <= xopt && vl >= 0) {
            dv = divisor(xl, vl)
            if (dv > 0) {
                a = a/dv
            } else {
                a = 0
            }
        }
    }
    if (md) {
        if (a < Afloor) {
            a = Afloor
        }
    }
    alpha_t = alt
    A = a
    UNITSON
}

: ---- Module 3 (kim_m3_force.mod) ----

: ---- the fixed step across eq 20's switch and the CE's error control (KimAct's switch_in_step, divided;
: KimForce's ce_step, check_step, split_step; KimForce's aa is acs here) ----

PROCEDURE switch_in_step(mv (1)) {
    : KimAct's switch_in_step (the length read into xl)
    : fixed step: where eq 20 switches within the step, for KimForce (which then integrates the step in two
    : parts): the played length and velocity are linear over the step (from the previous step's end values,
    : exactly as NEURON interpolates them between breakpoints on the step grid); ssw (1, in (0, 1)) is the
    : fraction of the step at which the condition Xm <= xopt, Vm >= 0 starts or stops holding, and asw the
    : activation before it (undivided, or divided at the middle of the part before); A, as always, is the
    : activation at the step's end.  ssw = 0: no switch within the step (asw = A).
    LOCAL c0, c1, lo, hi, r
    ssw = 0
    asw = A
    if (lengdiv && mv) {
        c0 = xmp <= xopt && vmp >= 0
        c1 = xl <= xopt && vm >= 0
        if (c0 != c1) {
            : the part [lo, hi] of the step where both linear conditions hold
            lo = 0
            hi = 1
            UNITSOFF
            if (xl != xmp) {
                r = (xopt - xmp)/(xl - xmp)
                if (xl > xmp) {
                    if (r < hi) {
                        hi = r
                    }
                } else if (r > lo) {
                    lo = r
                }
            }
            if (vm != vmp) {
                r = -vmp/(vm - vmp)
                if (vm < vmp) {
                    if (r < hi) {
                        hi = r
                    }
                } else if (r > lo) {
                    lo = r
                }
            }
            UNITSON
            if (c1) {
                : switched on at lo
                ssw = lo
                asw = ab
            } else {
                : switched off at hi
                ssw = hi
                asw = ab*divided(xmp + 0.5*hi*(xl - xmp), vmp + 0.5*hi*(vm - vmp))
            }
            if (movdep && asw < Afloor) {
                asw = Afloor
            }
            if (ssw <= 0 || ssw >= 1 || asw == A) {
                : no switch within the step, or one that changes nothing (beta = gamma = 0: the neutral
                : extension stays bit-identical to eq 20 off)
                ssw = 0
                asw = A
            }
        }
    }
}

FUNCTION divisor(x (mm), w (mm/s)) (1) {
    : eq 20's divisor (1 + beta phi(Xm)) (1 + gamma Vm) at Xm = x, Vm = w
    divisor = (1 + beta*(phi1*x + phi2))*(1 + gamma*w)
}

FUNCTION divided(x (mm), w (mm/s)) (1) {
    : eq 20's factor 1/divisor(x, w); 0 for a non-positive divisor
    LOCAL dv
    dv = divisor(x, w)
    if (dv > 0) {
        divided = 1/dv
    } else {
        divided = 0
    }
}

PROCEDURE ce_step(h (ms)) {
    LOCAL fe, fa
    : one fixed step of length h of the CE from xce at the length xl (F, vce, dvdF of that state already set):
    : acs (mm/ms) = the CE's mean velocity over the step
    : taut SE (or just taut and being taken up): F depends on xce; slack: it does not
    if (xl - xce > 0 || (xl - xce == 0 && vce < 0)) {
        dfdx = -kse*dvdF/(1000)
    } else {
        dfdx = 0
    }
    : one linearly implicit step: D = h f/(1 - h df/dxce)
    acs = (vce/(1000))/(1 - h*dfdx)
    if (xl - xce < 0 && xce + h*acs < xl) {
        : slack taken up within the step: stop where the SE becomes taut (no overshoot into the
        : stiff region by an explicit step)
        acs = (xl - xce)/h
    }
    if (Fc > 0) {
        fe = kse*(xl - xce - h*acs)
        fa = (2 + c0/P0)*Fc
        if (fe > Fc + asym*(fa - Fc)) {
            : the step would end on the steep saturation: backward Euler there (no overshoot)
            acs = ce_backward_euler(h, kse)
            nasym = nasym + 1
        } else if ((fe > Fc || Fse > Fc) && fabs((fe - Fse)/(1 (N))) > lincurv*(fa - fmax(fe, Fse))/(1 (N))) {
            : on eq 11 the force moves by more than lincurv of its distance to the pole within the step:
            : the linearised step is poor there (fast eccentric motion); backward Euler is not
            acs = ce_backward_euler(h, kse)
        } else if (fe < Fc && Fse < Fc && fabs((fe - Fse)/(1 (N))) > lincurv*(fmin(fe, Fse) + a0*Fc/P0)/(1 (N))) {
            : likewise on eq 10, whose pole is at F = -a0 Fc/P0: at low activation the Hill hyperbola bends
            : within a step and a linearised step overshoots into oscillation (a nearly silent unit moved)
            acs = ce_backward_euler(h, kse)
        } else if (Fse <= 0 || fe <= 0) {
            : slack, or at the SE's slack/taut boundary, where the Hill hyperbola bends sharply (pole at
            : F = -a0 Fc/P0): a linearised step (or stopping where the SE becomes taut) stalls at F = 0
            : while the CE should take up the slack and load the SE; backward Euler does not stall
            acs = ce_backward_euler(h, kse)
        }
    }
}
PROCEDURE check_step(h (ms), xla (mm), ala (1)) {
    : the local error of the step of length h just taken by ce_step (acs), estimated as half the change of the
    : CE velocity over it times k h (N, first order); above subtol times the force's scale the step is redone
    : as n = 1 + floor(err/(subtol scale)) (at most nsubmax) substeps of h/n along the length interpolated
    : from xla (the length at the step's start) to xl (a fast transient: A jumping at eq 20's switch at low
    : activation, where the CE-SE loop settles within a fraction of a step)
    LOCAL v0, fs0, xs, xle, ale, err, sc, n, i, nas, fe
    UNITSOFF
    v0 = vce
    fs0 = Fse
    xs = xce
    fe = kse*(xl - xce - h*acs)
    if (fe < 0) {
        fe = 0
    }
    Fse = fe
    velocity()
    err = 0.5*kse*h*fabs(v0 - vce)/1000
    sc = fmax(fmax(fs0, fe), Fc)
    if (err > subtol*sc) {
        n = 1 + floor(err/(subtol*sc))
        if (n > nsubmax) {
            n = nsubmax
        }
        nsub = nsub + 1
        nas = nasym
        xle = xl
        ale = al
        i = 1
        WHILE (i <= n) {
            xl = xla + (xle - xla)*i/n
            al = ala + (ale - ala)*i/n
            se_force()
            velocity()
            ce_step(h/n)
            xce = xce + h/n*acs
            i = i + 1
        }
        acs = (xce - xs)/h
        if (nasym > nas) {
            nasym = nas + 1
        }
        xce = xs
        xl = xle
        al = ale
        se_force()
    } else {
        Fse = fs0
    }
    velocity()
    UNITSON
}
PROCEDURE split_step(hs (ms)) {
    : fixed step across eq 20's switch at sw hs (KimAct's ssw): the CE advanced first with the activation before
    : it (KimAct's asw) over sw hs to the length interpolated there, then with A over the rest; acs is the mean
    : velocity over the whole step
    LOCAL xs, xle, ale, h1, xl1, nas
    UNITSOFF
    nsplit = nsplit + 1
    nas = nasym
    xs = xce
    xle = xl
    ale = al
    h1 = sw*hs
    xl1 = xlp + (xle - xlp)*sw
    al = asw
    xl = xl1
    se_force()
    velocity()
    ce_step(h1)
    if (nsubmax > 1 && Fc > 0) {
        check_step(h1, xlp, al)
    }
    xce = xce + h1*acs
    al = ale
    xl = xle
    se_force()
    velocity()
    ce_step(hs - h1)
    if (nsubmax > 1 && Fc > 0) {
        check_step(hs - h1, xl1, al)
    }
    xce = xce + (hs - h1)*acs
    acs = (xce - xs)/hs
    xce = xs
    if (nasym > nas) {
        nasym = nas + 1
    }
    se_force()
    velocity()
    UNITSON
}

FUNCTION fmin(a (N), b (N)) (N) {
    if (a < b) {
        fmin = a
    } else {
        fmin = b
    }
}

FUNCTION fmax(a (N), b (N)) (N) {
    if (a > b) {
        fmax = a
    } else {
        fmax = b
    }
}

FUNCTION ce_backward_euler(h (ms), ks (N/mm)) (mm/ms) {
    : KimForce's implicit_step: a backward-Euler step of the CE (safeguarded Newton on the step's end force); returns
    : its velocity (mm/ms), KimForce's aa
    LOCAL lo, hi, f, g, dg, i, rhs, fsave, done
    fsave = Fse
    rhs = ks*(xl - xce)
    Fse = 0
    velocity()
    g = ks*h*vce/(1000) - rhs
    if (g >= 0) {
        ce_backward_euler = vce/(1000)
    } else {
        lo = 0*rhs
        hi = rhs
        if (Fc > hi) {
            hi = Fc
        }
        f = 0.5*(lo + hi)
        i = 0
        done = 0
        WHILE (i < 100 && done == 0) {
            Fse = f
            velocity()
            g = f + ks*h*vce/(1000) - rhs
            UNITSOFF
            if (fabs(g) <= 1e-13*hi || hi - lo <= 1e-13*hi) {
            UNITSON
                done = 1
            } else {
                if (g > 0) {
                    hi = f
                } else {
                    lo = f
                }
                dg = 1 + ks*h*dvdF/(1000)
                f = f - g/dg
                if (f <= lo || f >= hi) {
                    f = 0.5*(lo + hi)
                }
            }
            i = i + 1
        }
        ce_backward_euler = (xl - f/ks - xce)/h
    }
    Fse = fsave
    velocity()
}

PROCEDURE se_force() {
    : KimForce's se_force(), each field read once into a LOCAL (the same arithmetic)
    LOCAL fs, p0, fc
    UNITSOFF
    p0 = P0
    fs = p0*KSE*(xl - xce)
    if (fs < 0) {
        fs = 0
    }
    Fse = fs
    F = fs
    if (xl != xmc) {
        gc = exp(-((xl - g1)/g2)^2)
        xmc = xl
    }
    fc = p0*gc*al
    if (fc < 0) {
        fc = 0
    } else if (fc > 0 && fc < fcmin*p0) {
        fc = fcmin*p0
    }
    Fc = fc
    UNITSON
}

PROCEDURE velocity() {
    : KimForce's velocity(), each field read once into a LOCAL (the same arithmetic; fewer field accesses)
    LOCAL Fa, fc, fs, p0, a0f, v, dv
    UNITSOFF
    fc = Fc
    fs = Fse
    if (fc <= 0) {
        dv = 0
        if (fs > 0) {
            v = vmax
        } else {
            v = 0
        }
    } else if (fs <= fc) {
        p0 = P0
        a0f = a0
        v = -b0*(fc - fs)/(fs + a0f*fc/p0)
        dv = b0*fc*(1 + a0f/p0)/((fs + a0f*fc/p0)*(fs + a0f*fc/p0))
    } else {
        Fa = (2 + c0/P0)*fc
        if (fs < Fa) {
            v = d0*(fs - fc)/(Fa - fs)
            dv = d0*(Fa - fc)/((Fa - fs)*(Fa - fs))
        } else {
            v = vmax
        }
        if (v >= vmax) {
            v = vmax
            dv = 0
        }
    }
    vce = v
    dvdF = dv
    UNITSON
}

INCLUDE "cvode_on.inc"

NET_RECEIVE(w (1)) {
    S2 = S2 + w
    S12 = S12 + w
    nspike = nspike + 1
}
