COMMENT
Module 2 of Kim, Sandercock & Heckman 2015 (seed 001): troponin-bound Ca2+ -> activation.

Equations (spec/kim2015_model.md): eq 8 (Morris-Lecar form), x = [CaSPT]/T0,
    Atil' = (Atil_inf - Atil)/tau_A,  Atil_inf = 0.5 (1 + tanh((x - C1)/C2)),  tau_A = C3/cosh((x - C4)/(2 C5))
    A = Atil^alpha
and the movement compensations on an explicit movement clock, each behind its own switch, for t >= onset (ms):
    movdep = 1 (eq 19):  alpha(t) = alpha + alpha1 (1 + tanh((t - onset - alpha2)/alpha3)), A = Atil^alpha(t),
                         and A >= Afloor (1e-3) while eq 19 is active
    lengdiv = 1 (eq 20): A = A / ((1 + beta phi(Xm)) (1 + gamma Vm))   if Xm <= xopt and Vm >= 0
                         (a non-positive divisor, possible only for phi(Xm) <= -1/beta, gives A = 0, never a
                         division by zero)
    Both on is the seed's movement compensation (kim_excitation(movement_compensation=True)).  With
    alpha(t) = 2, A = Atil*Atil (as in the static case): eq 19 with alpha1 = 0 is bit-identical to it off while
    A stays above the floor.
Units: C3, alpha2, alpha3 ms; gamma s/mm; Vm mm/s; Xm mm; phi1, phi3 /mm.

Coupling (documented interface, see neuromuscle/model/kim.py):
  POINTER caspt -> [CaSPT] (M) of the calcium mechanism (KimCa)
  POINTER T0, phi1, phi2, xopt -> KimCa's parameters of the same names (M, /mm, 1, mm): total troponin and the
                   eq 18 length factor below the optimum live in KimCa only, so setting one cannot make the two
                   modules disagree.
  POINTER xm, vm -> muscle length (mm) and velocity (mm/s) of a MuscleLength point process
  POINTER tauA_gain -> modulation port (1): tau_A is multiplied by it (an extension's RANGE output); read only
                   when use_ports = 1 (set by the Python wiring), else 1; x/1 is exact: off is bit-identical.
  POINTER C1_shift -> modulation port (1, normalised [CaSPT] as C1): the half-activation point of eq 8 moves to
                   C1 + C1_shift (Atil_inf = 0.5 (1 + tanh((x - C1 - C1_shift)/C2))); read only when
                   use_ports = 1, else 0; a shift of exactly 0 takes eq 8's own expression: off and neutral are
                   bit-identical (points at RANGE zero when unused).
  The shared parameters are read through their POINTERs once, at INITIAL (T0c, phi1c, phi2c, xoptc).
  RANGE A        <- read by the force mechanism (KimForce POINTER act).  Any excitation model that exposes an
                   activation A in [0, 1] can take this place in front of Module 3.
Numerics: linear in Atil, so METHOD cnexp is exact for frozen x in fixed step; CVODE uses the same block.
The movement clock switches at the onset in CVODE (an event there) and at the fixed step's midpoint (see states).
Fixed step: eq 20's switch within the step (Xm reaching xopt, Vm changing sign) is located on the played length and
velocity (linear between the previous step's end values and this one's) and reported to KimForce as RANGE ssw
(the fraction of the step; 0 when there is none or it changes nothing) and asw (the activation before it), so
that Module 3 integrates the two parts with their own activation; A stays the activation at the step's end.
ENDCOMMENT

NEURON {
    POINT_PROCESS KimAct
    THREADSAFE
    RANGE C1, C2, C3, C4, C5, alpha, alpha1, alpha2, alpha3, beta, gamma
    RANGE movdep, lengdiv, onset, Afloor, unity, zero, use_ports, rest
    RANGE A, alpha_t, Ainf, tauA, atil0, asw, ssw
    POINTER caspt, xm, vm, T0, phi1, phi2, xopt, tauA_gain, C1_shift
    RANGE T0c, phi1c, phi2c, xoptc
}

UNITS {
    (M) = (1/liter)
}

PARAMETER {
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
    unity = 1 (1)
    zero = 0 (1)
    use_ports = 0 (1)
    rest = 1 (1)
}

ASSIGNED {
    dt (ms)
    caspt (M)
    T0 (M)
    phi1 (/mm)
    phi2 (1)
    xopt (mm)
    tauA_gain (1)
    C1_shift (1)
    T0c (M)
    phi1c (/mm)
    phi2c (1)
    xoptc (mm)
    xm (mm)
    vm (mm/s)
    A (1)
    alpha_t (1)
    Ainf (1)
    tauA (ms)
    kA (/ms)
    ab (1)
    asw (1)
    ssw (1)
    xmp (mm)
    mvp (1)
    vmp (mm/s)
}

STATE {
    atil (1)
}

INITIAL {
    : KimCa's shared parameters, read once per run (they are constants of the run)
    T0c = T0
    phi1c = phi1
    phi2c = phi2
    xoptc = xopt
    if (rest) {
        : at rest Atil sits at its steady state for the resting [CaSPT] (KimCa's INITIAL has run: KimCa is
        : registered first)
        rates()
        atil = Ainf
    } else {
        atil = atil0
    }
    activation(t, 0)
    xmp = xm
    vmp = vm
    ssw = 0
    asw = A
    mvp = t >= onset
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    LOCAL mvn
    rates()
    atil' = (Ainf - atil)*kA
    if (cvode_on()) {
        : the movement clock runs from just after the onset: CVODE stops there (an event), and the step that
        : ends at the onset (whose implicit corrector evaluates this block at t = onset itself) still runs
        : without eqs 19-20, as the continuous model does; the restart at the onset then runs with them
        activation(t, 1)
    } else {
        : NEURON's fixed step updates the states with t at the step's end: the movement clock switches on
        : at the step's midpoint, so the step that ends at the onset still runs without eqs 19-20 (as the
        : continuous model and CVODE do) instead of one step early
        activation(t - 0.5*dt, 0)
        mvn = t - 0.5*dt >= onset
        switch_in_step(mvn)
        if (mvn && !mvp && ssw == 0 && (movdep || lengdiv)) {
            : the movement onset in this step: A jumped (eqs 19-20 switch on); ssw = -1 tells KimForce to hold
            : A of the step's end over its CE substeps instead of interpolating from the previous step's A
            ssw = -1
        }
        mvp = mvn
        xmp = xm
        vmp = vm
    }
}

PROCEDURE rates() {
    : eq 8 with exponentials only: 0.5 (1 + tanh(u)) = 1/(1 + exp(-2u)), cosh(v) = (e^v + e^-v)/2
    LOCAL x, ev
    x = caspt/T0c
    Ainf = 1/(1 + exp(-2*(x - C1)/C2))
    ev = exp((x - C4)/(2*C5))
    if (use_ports) {
        kA = 0.5*(ev + 1/ev)/C3/tauA_gain
        if (C1_shift != 0) {
            Ainf = 1/(1 + exp(-2*(x - C1 - C1_shift)/C2))
        }
    } else {
        kA = 0.5*(ev + 1/ev)/C3
    }
    tauA = 1/kA
}

PROCEDURE activation(tc (ms), strict (1)) {
    : tc: the time (ms) at which the movement clock's switch is read: moving when tc >= onset, or tc > onset
    : with strict = 1 (CVODE: the onset itself belongs to the step that ends there)
    LOCAL at, dv, mv
    if (strict) {
        mv = tc > onset
    } else {
        mv = tc >= onset
    }
    at = atil
    if (at < 0) {
        at = 0
    }
    if (movdep && mv) {
        : eq 19: alpha rises on the movement clock
        alpha_t = alpha + alpha1*(1 + tanh((t - onset - alpha2)/alpha3))
    } else {
        alpha_t = alpha
    }
    if (alpha_t == 2) {
        A = at*at
    } else {
        A = pow(at, alpha_t)
    }
    ab = A
    if (lengdiv && mv) {
        : eq 20: lengthening at or below the optimum
        if (xm <= xoptc && vm >= 0) {
            dv = divisor(xm, vm)
            if (dv > 0) {
                A = A/dv
            } else {
                A = 0
            }
        }
    }
    if (movdep && mv) {
        if (A < Afloor) {
            A = Afloor
        }
    }
}

PROCEDURE switch_in_step(mv (1)) {
    : fixed step: where eq 20 switches within the step, for KimForce (which then integrates the step in two
    : parts): the played length and velocity are linear over the step (from the previous step's end values,
    : exactly as NEURON interpolates them between breakpoints on the step grid); ssw (1, in (0, 1)) is the
    : fraction of the step at which the condition Xm <= xopt, Vm >= 0 starts or stops holding, and asw the
    : activation before it (undivided, or divided at the middle of the part before); A, as always, is the
    : activation at the step's end.  ssw = 0: no switch within the step (asw = A); the caller sets ssw = -1 for
    : the step of the movement onset (A jumped).
    LOCAL c0, c1, lo, hi, r
    ssw = 0
    asw = A
    if (lengdiv && mv) {
        c0 = xmp <= xoptc && vmp >= 0
        c1 = xm <= xoptc && vm >= 0
        if (c0 != c1) {
            : the part [lo, hi] of the step where both linear conditions hold
            lo = 0
            hi = 1
            UNITSOFF
            if (xm != xmp) {
                r = (xoptc - xmp)/(xm - xmp)
                if (xm > xmp) {
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
                asw = ab*divided(xmp + 0.5*hi*(xm - xmp), vmp + 0.5*hi*(vm - vmp))
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
    divisor = (1 + beta*(phi1c*x + phi2c))*(1 + gamma*w)
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

INCLUDE "cvode_on.inc"
