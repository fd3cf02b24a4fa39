COMMENT
Module 3 of Kim, Sandercock & Heckman 2015 (seed 001): activation -> force, a Hill/Mashima contractile
element (CE) in series with a linear series elastic element (SE).

Equations (spec/kim2015_model.md), eqs 9-12:
    F  = P0 KSE (dXm - dXCE), F = 0 where dXm - dXCE <= 0                      (eq 9)
    Fc = P0 g(Xm) A,  g(Xm) = exp(-((Xm - g1)/g2)^2)                          (eq 12)
    F <= Fc (shortening, Hill):     dXCE/dt = -b0 (Fc - F)/(F + a0 Fc/P0)      (eq 10)
    F >  Fc (lengthening, Mashima): dXCE/dt = -d0 (Fc - F)/(2 Fc - F + c0 Fc/P0) (eq 11)
Here XCE starts at the initial muscle length, so dXm - dXCE = Xm - XCE and the reference lengths cancel
(the spec's "start both references at the trial's length").
Units: lengths mm, forces N, velocities mm/s (the CE state moves in mm/ms = velocity/1000), KSE /mm.

The Mashima asymptote.  Eq 11's denominator vanishes at F = Fa = (2 + c0/P0) Fc and changes sign beyond it
(the published code then lets XCE run at 1e5 mm/s).  Here eq 11 is used up to Fl = Fc + asym (Fa - Fc)
(asym = 0.95) and continued beyond it by its tangent line, capped at vmax (mm/s): the CE yields fast and
monotonically, with no division blow-up.  Each fixed step spent beyond Fl is counted in nasym so the caller can
report it.  With no activation (Fc = 0) a taut SE makes the CE yield at vmax and a slack one does nothing.

Coupling: POINTER act -> activation A (1) of an excitation mechanism (KimAct, or any model exposing A);
          POINTER xm   -> muscle length (mm) of a MuscleLength point process;
          POINTER force_offset -> modulation port (N): a history-dependent element in parallel with the CE-SE
                   (force enhancement after stretch, depression after shortening) adds force_offset to the
                   output F = Fse + force_offset; the CE-SE dynamics see Fse only.  Unused, it points at this
                   mechanism's RANGE zero (= 0), and x + 0 is exact: off is bit-identical.
Numerics: fixed step: one linearly implicit (Rosenbrock-Euler) step with the exact dv/dF (L-stable for the
stiff SE-CE loop at low activation); CVODE: exact right-hand side written a - b XCE (see KimCa).
ENDCOMMENT

NEURON {
    POINT_PROCESS KimForce
    THREADSAFE
    RANGE P0, KSE, g1, g2, a0, b0, c0, d0, vmax, asym, F0, zero
    RANGE F, Fse, Fc, vce, nasym
    POINTER act, xm, force_offset
}

PARAMETER {
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
    F0 = 0 (N)
    zero = 0 (N)
}

ASSIGNED {
    dt (ms)
    act (1)
    xm (mm)
    force_offset (N)
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
    xl (mm)
    al (1)
}

STATE {
    xce (mm)
}

INITIAL {
    xl = xm
    al = act
    xce = xl - F0/(P0*KSE)
    nasym = 0
    xmc = 1e9
    se_force()
}

BREAKPOINT {
    SOLVE states METHOD euler
}

DERIVATIVE states {
    : the POINTERs are read once per evaluation into xl, al
    xl = xm
    al = act
    se_force()
    velocity()
    kse = P0*KSE
    : taut SE (or just taut and being taken up): F depends on xce; slack: it does not
    if (xl - xce > 0 || (xl - xce == 0 && vce < 0)) {
        dfdx = -kse*dvdF/(1000)
    } else {
        dfdx = 0
    }
    if (cvode_on()) {
        bb = -dfdx
        aa = vce/(1000) + bb*xce
    } else {
        : one linearly implicit step: D = h f/(1 - h df/dxce)
        aa = (vce/(1000))/(1 - dt*dfdx)
        if (xl - xce < 0 && xce + dt*aa < xl) {
            : slack taken up within the step: stop where the SE becomes taut (no overshoot into the
            : stiff region by an explicit step)
            aa = (xl - xce)/dt
        }
        bb = 0
        if (vce > 0 && Fse > 1e-3*P0 && Fse > Fc + asym*(Fc*(2 + c0/P0) - Fc)) {
            nasym = nasym + 1
        }
    }
    xce' = aa - bb*xce
    se_force()
}

PROCEDURE se_force() {
    Fse = P0*KSE*(xl - xce)
    if (Fse < 0) {
        Fse = 0
    }
    : a hoc user who leaves the port unset gets no offset (nrn_pointing), never a crash
    UNITSOFF
    if (nrn_pointing(force_offset)) {
        F = Fse + force_offset
    } else {
        F = Fse
    }
    UNITSON
    if (xl != xmc) {
        : force-length factor g(Xm) (eq 12), recomputed only when the length changes
        gc = exp(-((xl - g1)/g2)^2)
        xmc = xl
    }
    Fc = P0*gc*al
    if (Fc < 0) {
        Fc = 0
    }
}

PROCEDURE velocity() {
    : CE velocity vce (mm/s) of eqs 10-11 and dvdF = d vce / dF, continued past the Mashima asymptote
    LOCAL Fa, Fl, vl, sl
    if (Fc <= 0) {
        dvdF = 0
        if (Fse > 0) {
            vce = vmax
        } else {
            vce = 0
        }
    } else if (Fse <= Fc) {
        vce = -b0*(Fc - Fse)/(Fse + a0*Fc/P0)
        dvdF = b0*Fc*(1 + a0/P0)/((Fse + a0*Fc/P0)*(Fse + a0*Fc/P0))
    } else {
        Fa = (2 + c0/P0)*Fc
        Fl = Fc + asym*(Fa - Fc)
        if (Fse <= Fl) {
            vce = d0*(Fse - Fc)/(Fa - Fse)
            dvdF = d0*(Fa - Fc)/((Fa - Fse)*(Fa - Fse))
        } else {
            vl = d0*(Fl - Fc)/(Fa - Fl)
            sl = d0*(Fa - Fc)/((Fa - Fl)*(Fa - Fl))
            vce = vl + sl*(Fse - Fl)
            dvdF = sl
            if (vce > vmax) {
                vce = vmax
                dvdF = 0
            }
        }
    }
}

INCLUDE "cvode_on.inc"
