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

The Mashima asymptote.  Eq 11's denominator vanishes at F = Fa = (2 + c0/P0) Fc: as F nears Fa the CE yields
ever faster, so the force stays below Fa however fast the muscle is stretched (the published code lets XCE run
at 1e5 mm/s past Fa instead).  Here eq 11 is used as it stands up to Fa, its velocity capped at vmax (1e5 mm/s,
beyond any muscle): v = min(d0 (F - Fc)/(Fa - F), vmax), and vmax from Fa on.  The force therefore stays below
the point where eq 11 reaches vmax, a hair under Fa, unless the muscle is stretched faster than vmax.  CVODE
integrates exactly this right-hand side.  The fixed step uses the linearly implicit step below; where that
step would end beyond Fl = Fc + asym (Fa - Fc) (asym = 0.95: the steep part, where a linearised step
overshoots the pole), and at the SE's slack/taut boundary (where the Hill hyperbola bends so sharply that a
linearised step stalls at F = 0), and on eq 11 wherever the force would move by more than lincurv (2 %) of its
distance to the pole within one step (fast eccentric motion), and likewise on eq 10 relative to its pole at
F = -a0 Fc/P0 (a nearly silent unit moved: at low activation the hyperbola bends within a step and a linearised
step oscillates), it takes a backward-Euler step of the same
equation instead, solving F + k h v(F) = k (Xm - XCE) for the step's end force F (k = P0 KSE; safeguarded
Newton).  Isometric and shortening trials never meet these cases, so their numbers are unchanged.  nasym counts the fixed
steps that end beyond Fl: information (the CE was yielding), not an error.  With no activation (Fc = 0) a taut
SE makes the CE yield at vmax and a slack one does nothing.

A floor on the CE capacity: a positive Fc below fcmin P0 (fcmin = 1e-4, below any measurable force) is taken
as fcmin P0 in eqs 10-11.  The CE-SE loop's stiffness grows as P0 KSE b0/Fc and its nonlinear region shrinks
as Fc/(P0 KSE): with Fc -> 0 (a nearly silent unit, e.g. a parameter set whose resting A is 1e-9) CVODE's
corrector failed or crawled at h ~ 1e-7 ms.  Fc = 0 (no activation at all) is left as it is, and every
published set's resting Fc is far above the floor (CT09: 0.0036 P0), so their numbers do not move.
(neuromuscle.analysis.module3.FC_FLOOR is the same number for the SciPy twin.)

The CE state is its length change since INITIAL, dxce = XCE - x0 (mm; x0 the muscle length at INITIAL), and XCE
= x0 + dxce (RANGE xce, read by extensions).  The model is the same; the reason is CVODE's error test, which
weighs each state's error by rtol |y| + atol: with XCE itself as the state (|XCE| ~ 10 mm) rtol 1e-6 let the CE
length err by 1e-5 mm, i.e. P0 KSE 1e-5 ~ 1e-4 N of force whatever the force, up to 4.8 % of the peak of a weakly
activated unit (sweep draws 7 and 23: a ramp's onset; 0.009 % with dxce).  |dxce| is of the order of the SE's
extension plus the length change, so rtol now acts on the force's own scale.

Two more fixed-step rules (both O(1) per step; isometric and shortening trials of the published sets never meet
them, so their numbers are unchanged):
- error control: after the step, its local error is estimated as k h |v(start) - v(end)|/2 (N, the first-order
  term) and, above subtol (1e-3) times the force's scale max(F, Fc), the step is redone as n = 1 + floor(err/
  (subtol scale)) substeps (at most nsubmax = 64; nsubmax = 1 turns it off) along the length interpolated from
  the previous step's, and with the activation interpolated likewise from the previous step's A (held at the
  step's end's A over every substep, a regenerative twitch's fall, where F follows eq 11's asymptote as A
  collapses, was 1.1 % of peak off: sweep draw 524; 0.6 % interpolated), except where KimAct reports ssw = -1
  (the movement onset's step, where A jumps: interpolating there was 2.6 % off) (RANGE nsub counts them).  A fast transient needs it: at low activation the CE-SE
  loop settles within a fraction of a step when A jumps (sweep draw 13: 2.8 -> 0.25 % of peak), and a weak
  unit's SE taking up slack loads in ~0.01 ms (draw 476, peak 0.0018 N: 1.23 % with at most 16 substeps, whose
  backward-Euler error on that transient remained; 0.28 % with 64).  The cap bounds the cost of the rare steps
  that need it; random length's cost did not change measurably.
- eq 20's switch within the step: KimAct reports where in the step (ssw, a fraction) the lengthening-below-the-
  optimum condition starts or stops holding and the activation before it (asw); the step is then taken in two
  parts, asw over ssw dt and A over the rest (RANGE nsplit counts them).  Before, A of the step's end held over
  the whole step (sweep draw 25, Xm crossing the optimum in a 200 mm/s ramp: 1.6 -> 0.3 % of peak).  POINTER asw,
  ssw are optional: unset (nrn_pointing) or pointing at 0, the step is not split (an excitation model without
  eq 20).

Coupling: POINTER act -> activation A (1) of an excitation mechanism (KimAct, or any model exposing A);
          POINTER xm   -> muscle length (mm) of a MuscleLength point process;
          POINTER force_offset -> modulation port (N): a history-dependent element in parallel with the CE-SE
                   (force enhancement after stretch, depression after shortening) adds force_offset to the
                   output F = Fse + force_offset; the CE-SE dynamics see Fse only.  Read only when use_ports = 1
                   (set by the Python wiring, which points it at RANGE zero when unused), else 0.
Numerics: fixed step: one linearly implicit (Rosenbrock-Euler) step with the exact dv/dF (L-stable for the
stiff SE-CE loop at low activation); F and vce are then recomputed from the updated XCE, so the fixed step
reports the force at the step's end (as CVODE does), not at its start; CVODE: exact right-hand side written
a - b XCE (see KimCa).
ENDCOMMENT

NEURON {
    POINT_PROCESS KimForce
    THREADSAFE
    RANGE P0, KSE, g1, g2, a0, b0, c0, d0, vmax, asym, lincurv, fcmin, F0, zero, use_ports, rest
    RANGE F, Fse, Fc, vce, nasym, xce, x0, subtol, nsubmax, nsub, nsplit
    POINTER act, xm, force_offset, asw, ssw
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
    lincurv = 0.02 (1)
    fcmin = 1e-4 (1)
    subtol = 1e-3 (1)
    nsubmax = 64 (1)
    F0 = 0 (N)
    zero = 0 (N)
    use_ports = 0 (1)
    rest = 1 (1)
}

ASSIGNED {
    dt (ms)
    act (1)
    xm (mm)
    force_offset (N)
    asw (1)
    ssw (1)
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
    fend (N)
    Fasym (N)
    xmc (mm)
    gc (1)
    xl (mm)
    al (1)
    xce (mm)
    x0 (mm)
    xlp (mm)
    alp (1)
    nsub (1)
    nsplit (1)
    sw (1)
}

STATE {
    dxce (mm)
}

INITIAL {
    xl = xm
    al = act
    xmc = 1e9
    x0 = xl
    dxce = 0
    xce = x0
    se_force()
    if (rest) {
        : isometric equilibrium with the initial activation: the SE carries the CE's force Fc (no creep)
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
    if (!cvode_on()) {
        : fixed step: report F and vce of the updated CE state (the DERIVATIVE block's are the step's start)
        xl = xm
        al = act
        xce = x0 + dxce
        se_force()
        velocity()
        xlp = xl
        alp = al
    }
}

DERIVATIVE states {
    : the POINTERs are read once per evaluation into xl, al
    xl = xm
    al = act
    xce = x0 + dxce
    se_force()
    velocity()
    kse = P0*KSE
    if (cvode_on()) {
        : taut SE (or just taut and being taken up): F depends on xce; slack: it does not
        if (xl - xce > 0 || (xl - xce == 0 && vce < 0)) {
            dfdx = -kse*dvdF/(1000)
        } else {
            dfdx = 0
        }
        bb = -dfdx
        aa = vce/(1000) + bb*dxce
    } else {
        bb = 0
        sw = 0
        if (nrn_pointing(ssw)) {
            sw = ssw
        }
        if (sw > 0 && sw < 1) {
            split_step()
        } else {
            ce_step(dt)
            if (nsubmax > 1 && Fc > 0) {
                if (sw < 0) {
                    : A jumped at the step's start (KimAct: the movement onset): hold it over the substeps
                    check_step(dt, xlp, al)
                } else {
                    check_step(dt, xlp, alp)
                }
            }
        }
    }
    dxce' = aa - bb*dxce
    se_force()
}

PROCEDURE ce_step(h (ms)) {
    : one fixed step of length h of the CE from xce at the length xl (F, vce, dvdF of that state already set):
    : aa (mm/ms) = the CE's mean velocity over the step
    : taut SE (or just taut and being taken up): F depends on xce; slack: it does not
    if (xl - xce > 0 || (xl - xce == 0 && vce < 0)) {
        dfdx = -kse*dvdF/(1000)
    } else {
        dfdx = 0
    }
    : one linearly implicit step: D = h f/(1 - h df/dxce)
    aa = (vce/(1000))/(1 - h*dfdx)
    if (xl - xce < 0 && xce + h*aa < xl) {
        : slack taken up within the step: stop where the SE becomes taut (no overshoot into the
        : stiff region by an explicit step)
        aa = (xl - xce)/h
    }
    if (Fc > 0) {
        fend = kse*(xl - xce - h*aa)
        Fasym = (2 + c0/P0)*Fc
        if (fend > Fc + asym*(Fasym - Fc)) {
            : the step would end on the steep saturation: backward Euler there (no overshoot)
            implicit_step(h)
            nasym = nasym + 1
        } else if ((fend > Fc || Fse > Fc) && fabs((fend - Fse)/(1 (N))) > lincurv*(Fasym - fmax(fend, Fse))/(1 (N))) {
            : on eq 11 the force moves by more than lincurv of its distance to the pole within the step:
            : the linearised step is poor there (fast eccentric motion); backward Euler is not
            implicit_step(h)
        } else if (fend < Fc && Fse < Fc && fabs((fend - Fse)/(1 (N))) > lincurv*(fmin(fend, Fse) + a0*Fc/P0)/(1 (N))) {
            : likewise on eq 10, whose pole is at F = -a0 Fc/P0: at low activation the Hill hyperbola bends
            : within a step and a linearised step overshoots into oscillation (a nearly silent unit moved)
            implicit_step(h)
        } else if (Fse <= 0 || fend <= 0) {
            : slack, or at the SE's slack/taut boundary, where the Hill hyperbola bends sharply (pole at
            : F = -a0 Fc/P0): a linearised step (or stopping where the SE becomes taut) stalls at F = 0
            : while the CE should take up the slack and load the SE; backward Euler does not stall
            implicit_step(h)
        }
    }
}

PROCEDURE check_step(h (ms), xla (mm), ala (1)) {
    : the local error of the step of length h just taken by ce_step (aa), estimated as half the change of the
    : CE velocity over it times k h (N, first order); above subtol times the force's scale the step is redone
    : as n = 1 + floor(err/(subtol scale)) (at most nsubmax) substeps of h/n along the length interpolated
    : from xla (the length at the step's start) to xl (a fast transient: A jumping at eq 20's switch at low
    : activation, where the CE-SE loop settles within a fraction of a step)
    LOCAL v0, fs0, xs, xle, ale, err, sc, n, i, nas, fe
    UNITSOFF
    v0 = vce
    fs0 = Fse
    xs = xce
    fe = kse*(xl - xce - h*aa)
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
            xce = xce + h/n*aa
            i = i + 1
        }
        aa = (xce - xs)/h
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

PROCEDURE split_step() {
    : fixed step across eq 20's switch at sw dt (KimAct's ssw): the CE advanced first with the activation before
    : it (KimAct's asw) over sw dt to the length interpolated there, then with A over the rest; aa is the mean
    : velocity over the whole step
    LOCAL xs, xle, ale, h1, xl1, nas
    UNITSOFF
    nsplit = nsplit + 1
    nas = nasym
    xs = xce
    xle = xl
    ale = al
    h1 = sw*dt
    xl1 = xlp + (xle - xlp)*sw
    al = asw
    xl = xl1
    se_force()
    velocity()
    ce_step(h1)
    if (nsubmax > 1 && Fc > 0) {
        check_step(h1, xlp, al)
    }
    xce = xce + h1*aa
    al = ale
    xl = xle
    se_force()
    velocity()
    ce_step(dt - h1)
    if (nsubmax > 1 && Fc > 0) {
        check_step(dt - h1, xl1, al)
    }
    xce = xce + (dt - h1)*aa
    aa = (xce - xs)/dt
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

PROCEDURE implicit_step(h (ms)) {
    : a backward-Euler step of the CE: aa = (XCE(t+h) - XCE)/h with F(t+h) the root of
    : g(F) = F + k h v(F)/1000 - k (xl - xce), increasing in F.  If g(0) >= 0 the SE is slack at the step's end
    : and the CE moves at v(0); else the root lies in (0, max(k (xl - xce), Fc)): Newton steps kept inside the
    : shrinking bracket, else bisection, to 1e-13 relative
    LOCAL lo, hi, f, g, dg, i, rhs, fsave, done
    fsave = Fse
    rhs = kse*(xl - xce)
    Fse = 0
    velocity()
    g = kse*h*vce/(1000) - rhs
    if (g >= 0) {
        aa = vce/(1000)
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
            g = f + kse*h*vce/(1000) - rhs
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
                dg = 1 + kse*h*dvdF/(1000)
                f = f - g/dg
                if (f <= lo || f >= hi) {
                    f = 0.5*(lo + hi)
                }
            }
            i = i + 1
        }
        aa = (xl - f/kse - xce)/h
    }
    Fse = fsave
    velocity()
}

PROCEDURE se_force() {
    Fse = P0*KSE*(xl - xce)
    if (Fse < 0) {
        Fse = 0
    }
    if (use_ports) {
        F = Fse + force_offset
    } else {
        F = Fse
    }
    if (xl != xmc) {
        : force-length factor g(Xm) (eq 12), recomputed only when the length changes
        gc = exp(-((xl - g1)/g2)^2)
        xmc = xl
    }
    Fc = P0*gc*al
    if (Fc < 0) {
        Fc = 0
    } else if (Fc > 0 && Fc < fcmin*P0) {
        : the floor on a positive capacity (see the header)
        Fc = fcmin*P0
    }
}

PROCEDURE velocity() {
    : CE velocity vce (mm/s) of eqs 10-11 and dvdF = d vce / dF: eq 11 up to its asymptote Fa, capped at vmax
    LOCAL Fa
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
        if (Fse < Fa) {
            vce = d0*(Fse - Fc)/(Fa - Fse)
            dvdF = d0*(Fa - Fc)/((Fa - Fse)*(Fa - Fse))
        } else {
            vce = vmax
        }
        if (vce >= vmax) {
            vce = vmax
            dvdF = 0
        }
    }
}

INCLUDE "cvode_on.inc"
