TITLE Hatze's triceps surae muscle-tendon complex in angular coordinates (van Zandwijk et al. 1998)

COMMENT
Hatze's triceps surae muscle-tendon complex (MTC) in angular coordinates (van Zandwijk et al. 1998, section 2.1.1;
docs/reference/hatze.md), the NEURON twin of neuromuscle/hatze/contraction.py (same equations).

A contractile element (CE) in parallel with a PEE, in series with an SEE; "lengths" are angles (rad), moments
N m, angular velocities rad/s, and the model's time is in SECONDS (NEURON's t is in ms).
    phi_mtc = phi_ce + phi_see,   M = M_see = M_ce + M_pee
    M_iso(phi_ce) = Mmax (1 - ((phi_ce/phi_ce_opt - 1)/w)^2), clipped at 0           (moment-angle parabola)
    F0 = q M_iso(phi_ce),  q = act (POINTER, the active state)                      (q enters only here)
    shortening, M <= F0 (eq 1):  omega_ce = (F0 - M) b/(M + a),  a = a_rel Mmax, b = b_rel phi_ce_opt
    lengthening, M > F0 (not in the paper; Van Soest & Bobbert 1993 eccentric hyperbola): with D = M - F0,
        r = D/(0.5 F0), v = -omega_ce = b_e r/(1 - r), b_e = F0 b/(4 (F0 + a)) (asymptote 1.5 F0, slope
        dM/dv at v = 0 twice the concentric one); from r = 0.8 on v continues linearly in M (C1).
    SEE (eq 2):  M_see = k_see e^2 for e > 0, else 0;  e = phi_mtc_offset + e_test + phi_ce_opt - phi_ce
    PEE:         M_pee = k_pee (phi_ce - phi_pee0_rel phi_ce_opt)^2 beyond its slack (k_pee = 0 in the paper)
    SEE slack:   CE at phi_ce_opt exerting Mmax (+ PEE there) when the MTC is at the test angle (ankle 100 deg):
                 e_test = sqrt((Mmax + M_pee(phi_ce_opt))/k_see), computed here in INITIAL (as
                 contraction.see_extension_at_test); the MTC angle enters only through its offset from the test
                 angle, phi_mtc_offset (rad, > 0 = MTC longer = ankle dorsiflexed below 100 deg), a RANGE
                 parameter that is set for isometric runs or driven by Vector.play(mtc._ref_phi_mtc_offset, ...).
    State: phi_ce (rad), d phi_ce/dt_ms = -omega_ce/1000 (omega_ce > 0 = shortening).

Coupling: POINTER act -> active state q (1): HatzeExc.A (eq 9) or Kim's KimAct.A, or any RANGE variable holding a
          number in [0, 1] (e.g. MuscleLength.xm set to a constant activation).
          Optional length-dependent activation (eq 9's rho*(xi), xi = phi_ce/phi_ce_opt): set xi_feedback = 1
          and point POINTER xi_exc at HatzeExc.xi; HatzeMTC then writes xi = phi_ce/phi_ce_opt there in INITIAL
          and after every state evaluation.  HatzeExc (registered before HatzeMTC) therefore uses xi from the
          previous evaluation: a lag of one step (fixed) or one right-hand side evaluation (CVODE).  With
          xi_feedback = 0 (default) xi_exc is never written and need not be set (neuromuscle.model.hatze points
          it at this mechanism's own RANGE xi_sink); with xi_feedback = 1 it must point somewhere.
Outputs:  M (Nm, MTC = SEE moment), phi_ce (rad, state), omega_ce (rad/s), F0 (Nm), e_test (rad),
          nbad (count of evaluations with M <= -a, where Hill's equation is singular; the denominator is then
          held at 1e-6 a -- only possible with a PEE pulling the CE, never with k_pee = 0).
INITIAL:  the CE starts at isometric equilibrium M_see - M_pee = q M_iso(phi_ce) for the initial act and
          phi_mtc_offset (bisection to machine precision, as contraction.equilibrium_phi_ce); where no equilibrium
          exists (the SEE cannot be stretched enough) noeq = 1 and the CE starts where the SEE is just slack.
Numerics: fixed step: one linearly implicit (Rosenbrock-Euler) step of phi_ce with the analytic
          df/dphi_ce (L-stable for the stiff eccentric-branch/SEE mode); CVODE: the exact right-hand side in the
          a - b y form with b = -df/dphi_ce (see KimForce).
ENDCOMMENT

NEURON {
    POINT_PROCESS HatzeMTC
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
    RANGE k_see, phi_ce_opt, Mmax, a_rel, b_rel, w, k_pee, phi_pee0_rel, phi_mtc_offset, xi_feedback
    RANGE M, omega_ce, F0, e_test, nbad, noeq, xi_sink, tstep
    POINTER act, xi_exc
}

UNITS {
    (Nm) = (newton meter)
}

PARAMETER {
    : Table 1, subject 3
    k_see = 377 (Nm)
    phi_ce_opt = 1.2 (1)
    Mmax = 52 (Nm)
    a_rel = 0.21 (1)
    b_rel = 1.55 (/s)
    w = 0.56 (1)
    k_pee = 0 (Nm)
    phi_pee0_rel = 1 (1)
    phi_mtc_offset = 0 (1)
    xi_feedback = 0 (1)
    xi_sink = 1 (1)
    variable_step = 0 (1)
}

ASSIGNED {
    dt (ms)
    tstep (ms)
    act (1)
    xi_exc (1)
    M (Nm)
    omega_ce (/s)
    F0 (Nm)
    e_test (1)
    nbad (1)
    noeq (1)
    fr (/ms)
    jac (/ms)
    aa (/ms)
    bb (/ms)
}

STATE {
    phi_ce (1)
}

INITIAL {
    LOCAL mp, lo, hi, mid, g, i, top, span
    nbad = 0
    noeq = 0
    mp = pee(phi_ce_opt)
    e_test = sqrt((Mmax + mp)/k_see)
    top = phi_mtc_offset + e_test + phi_ce_opt
    span = sqrt(4*Mmax/k_see) + 1e-9
    lo = top - span
    hi = top
    if (eqres(lo, top) <= 0) {
        noeq = 1
        phi_ce = top
    } else {
        i = 0
        mid = 0.5*(lo + hi)
        WHILE (i <= 200 && mid > lo && mid < hi) {
            : bisection until the interval cannot shrink (machine precision)
            g = eqres(mid, top)
            if (g > 0) {
                lo = mid
            } else {
                hi = mid
            }
            mid = 0.5*(lo + hi)
            i = i + 1
        }
        phi_ce = 0.5*(lo + hi)
    }
    rhs(phi_ce)
    feed_xi()
    tstep = t
}

BREAKPOINT {
    SOLVE states METHOD euler
}

DERIVATIVE states {
    LOCAL nst
    rhs(phi_ce)
    if (variable_step) {
        bb = -jac
        aa = fr + bb*phi_ce
    } else {
        : one linearly implicit step: D = h f/(1 - h df/dphi), h the whole step (dt is halved in this block
        : under secondorder: fixed_step.inc)
        nst = euler_steps(t, tstep, dt)
        aa = fr/(1 - dt*nst*jac)
        bb = 0
    }
    tstep = t
    phi_ce' = aa - bb*phi_ce
}

INCLUDE "fixed_step.inc"

AFTER SOLVE {
    : outputs at the new state (fixed step); under CVODE the DERIVATIVE evaluation has set them already
    rhs(phi_ce)
    feed_xi()
}

FUNCTION pee(phi (1)) (Nm) {
    LOCAL d
    d = phi - phi_pee0_rel*phi_ce_opt
    if (d > 0) {
        pee = k_pee*d*d
    } else {
        pee = 0
    }
}

FUNCTION miso(phi (1)) (Nm) {
    LOCAL x
    x = (phi/phi_ce_opt - 1)/w
    if (x < 1 && x > -1) {
        miso = Mmax*(1 - x*x)
    } else {
        miso = 0
    }
}

FUNCTION eqres(phi (1), top (1)) (Nm) {
    : isometric equilibrium residual M_see - M_pee - q M_iso at CE angle phi (SEE slack at phi = top)
    LOCAL e, q
    e = top - phi
    q = act
    if (q < 0) {
        q = 0
    }
    if (e > 0) {
        eqres = k_see*e*e - pee(phi) - q*miso(phi)
    } else {
        eqres = -pee(phi) - q*miso(phi)
    }
}

PROCEDURE feed_xi() {
    if (xi_feedback) {
        xi_exc = phi_ce/phi_ce_opt
    }
}

PROCEDURE rhs(phi (1)) {
    : sets M, F0, omega_ce (rad/s), fr = d phi_ce/dt (rad/ms) and jac = d fr/d phi_ce (/ms)
    LOCAL e, msee, dmsee, mpee, dmpee, d, mce, dm, x, mi, dmi, q, df0, a, b, om, om_m, om_f0, den, fa, ce, rc, k1, k2, vecc, dvdd
    a = a_rel*Mmax
    b = b_rel*phi_ce_opt
    e = phi_mtc_offset + e_test + phi_ce_opt - phi
    if (e > 0) {
        msee = k_see*e*e
        dmsee = 2*k_see*e
    } else {
        : zero in the units of the other branch (modlunit infers a LOCAL's unit from its last assignment)
        msee = 0*k_see
        dmsee = 0*k_see
    }
    d = phi - phi_pee0_rel*phi_ce_opt
    if (d > 0) {
        mpee = k_pee*d*d
        dmpee = 2*k_pee*d
    } else {
        mpee = 0*k_pee
        dmpee = 0*k_pee
    }
    M = msee
    mce = msee - mpee
    dm = -dmsee - dmpee
    x = (phi/phi_ce_opt - 1)/w
    if (x < 1 && x > -1) {
        mi = Mmax*(1 - x*x)
        dmi = -2*Mmax*x/(w*phi_ce_opt)
    } else {
        mi = 0*Mmax
        dmi = 0*Mmax
    }
    q = act
    F0 = q*mi
    if (F0 < 0) {
        F0 = 0
        df0 = 0*Mmax
    } else {
        df0 = q*dmi
    }
    if (mce <= F0) {
        : shortening, eq 1
        den = mce + a
        if (den < 1e-6*a) {
            den = 1e-6*a
            nbad = nbad + 1
        }
        om = (F0 - mce)*b/den
        om_m = -b*(F0 + a)/(den*den)
        om_f0 = b/den
    } else {
        : lengthening: eccentric hyperbola, linear from r = 0.8 on (contraction._ce_velocity_partials)
        d = mce - F0
        fa = F0 + a
        ce = b/(2*fa)
        rc = 0.8
        if (2*d < rc*F0) {
            den = F0 - 2*d
            vecc = ce*d*F0/den
            dvdd = ce*F0*F0/(den*den)
            : d vecc/d F0 at fixed M = (d vecc/d F0 at fixed D) - dvdd
            om_f0 = -((-ce/fa)*d*F0/den - 2*ce*d*d/(den*den) - dvdd)
        } else {
            k1 = 1/(1 - rc) - 1/((1 - rc)*(1 - rc))
            k2 = 1/((1 - rc)*(1 - rc))
            vecc = ce*(0.5*F0*rc*k1 + d*k2)
            dvdd = ce*k2
            om_f0 = -((-ce/fa)*(0.5*F0*rc*k1 + d*k2) + ce*0.5*rc*k1 - dvdd)
        }
        om = -vecc
        om_m = -dvdd
    }
    omega_ce = om
    fr = -om/(1000)
    jac = -(om_m*dm + om_f0*df0)/(1000)
}
