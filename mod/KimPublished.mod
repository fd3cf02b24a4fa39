TITLE Kim, Sandercock & Heckman 2015, Modules 1-2 integrated as the published code does (benchmark only)

COMMENT
Modules 1-2 of Kim, Sandercock & Heckman 2015 integrated the authors' way, for benchmarks only.

Same equations as KimCa + KimAct (eqs 1-8, 18, static alpha), but as the published code does it: one
DERIVATIVE block solved by derivimplicit (a Newton iteration every step) and release (eq 3) summed over the
spike history at every evaluation.  The history holds at most 10000 spikes; a further spike sets overflow = 1
(which the benchmark checks and reports) instead of overrunning silently as the published 1000-entry array did.
It exposes A for KimForce (POINTER act) exactly like KimAct.  Units as in KimCa/KimAct (ms, M, mm).
ENDCOMMENT

NEURON {
    POINT_PROCESS KimPublished
    THREADSAFE
    RANGE K1, K2, K3, K4, K5i, K6i, K, Rmax, Umax, tau1, tau2, CS0, B0, T0, CaSR0
    RANGE phi1, phi2, phi3, phi4, xopt, lencomp, C1, C2, C3, C4, C5, alpha
    RANGE A, nspike, overflow
    POINTER xm
}

UNITS {
    (M) = (1/liter)
}

DEFINE NMAX 10000

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
}

ASSIGNED {
    xm (mm)
    A (1)
    nspike (1)
    overflow (1)
    spk[NMAX] (ms)
    R (M/ms)
    U (M/ms)
}

STATE {
    CaSR (M)
    CaSRCS (M)
    CaSP (M)
    CaSPB (M)
    CaSPT (M)
    atil (1)
}

INITIAL {
    CaSR = CaSR0
    CaSRCS = 0
    CaSP = 0
    CaSPB = 0
    CaSPT = 0
    atil = 0
    nspike = 0
    overflow = 0
    A = 0
}

BREAKPOINT {
    SOLVE states METHOD derivimplicit
    A = pow(atil, alpha)
}

DERIVATIVE states {
    LOCAL s, i, d, c, z, w, K5, K6, ph, x
    s = 0
    FROM i = 0 TO nspike - 1 {
        : release kernel summed over the whole spike history (the published code's O(n) per evaluation)
        d = t - spk[i]
        if (d >= 0) {
            s = s + (1 - exp(-d/tau1))*exp(-d/tau2)
        }
    }
    R = CaSR*Rmax*s
    c = CaSP
    if (c < 0) {
        c = 0*CaSP
    }
    z = c*c*K*K
    w = z/(1 + c*K + z)
    U = Umax*w*w
    if (xm <= xopt) {
        ph = phi1*xm + phi2
    } else {
        ph = phi3*xm + phi4
    }
    if (lencomp) {
        K5 = K5i*ph
    } else {
        K5 = K5i
    }
    K6 = K6i/(1 + 5*atil)
    CaSR' = -K1*CaSR*(CS0 - CaSRCS) + K2*CaSRCS - R + U
    CaSRCS' = K1*CaSR*(CS0 - CaSRCS) - K2*CaSRCS
    CaSP' = -K5*CaSP*(T0 - CaSPT) + K6*CaSPT - K3*CaSP*(B0 - CaSPB) + K4*CaSPB + R - U
    CaSPB' = K3*CaSP*(B0 - CaSPB) - K4*CaSPB
    CaSPT' = K5*CaSP*(T0 - CaSPT) - K6*CaSPT
    x = CaSPT/T0
    atil' = (0.5*(1 + tanh((x - C1)/C2)) - atil)/(C3/cosh((x - C4)/(2*C5)))
}

NET_RECEIVE(w (1)) {
    : a full history is flagged (overflow = 1) and the spike dropped; the caller must check overflow
    if (nspike >= NMAX) {
        overflow = 1
    } else {
        spk[nspike] = t
        nspike = nspike + 1
    }
}
