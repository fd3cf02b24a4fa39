TITLE Kim, Sandercock & Heckman 2015, Module 2: troponin-bound Ca2+ to activation (KimAct)

COMMENT
Module 2 of the three-module muscle of Kim, Sandercock & Heckman 2015: troponin-bound Ca2+ -> activation.

Equations: eq 8 of the paper (Morris-Lecar form), x = [CaSPT]/T0,
    Atil' = (Atil_inf - Atil)/tau_A,  Atil_inf = 0.5 (1 + tanh((x - C1)/C2)),  tau_A = C3/cosh((x - C4)/(2 C5))
    A = Atil^alpha
and the movement compensations on an explicit movement clock, each behind its own switch, for t >= onset (ms):
    movdep = 1 (eq 19):  alpha(t) = alpha + alpha1 (1 + tanh((t - onset - alpha2)/alpha3)), A = Atil^alpha(t),
                         and A >= Afloor (1e-3) while eq 19 is active
    lengdiv = 1 (eq 20): A = A / ((1 + beta phi(Xm)) (1 + gamma Vm))   if Xm <= xopt and Vm >= 0
                         (a non-positive divisor, possible only for phi(Xm) <= -1/beta, gives A = 0, never a
                         division by zero)
    Both on is the paper's movement compensation (kim_excitation(movement_compensation=True)).  With
    alpha(t) = 2, A = Atil*Atil (as in the static case): eq 19 with alpha1 = 0 is bit-identical to it off while
    A stays above the floor.
They are written once in kim_m2_activation.inc (shared with the fused KimUnit).
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
Numerics: fixed step: eq 8 is linear in Atil, advanced exactly for the step's [CaSPT] (the cnexp formula, written
out so that every engine computes the same numbers) and handed to METHOD euler as the state itself (its derivative
is then zero); CVODE (variable_step = 1): the exact right-hand side.
The movement clock switches at the onset in CVODE (an event there) and at the fixed step's midpoint.
Fixed step: eq 20's switch within the step (Xm reaching xopt, Vm changing sign) is located on the played length and
velocity (linear between the previous step's end values and this one's) and reported to KimForce as RANGE ssw
(the fraction of the step; 0 when there is none or it changes nothing) and asw (the activation before it), so
that Module 3 integrates the two parts with their own activation; A stays the activation at the step's end.
ENDCOMMENT

NEURON {
    POINT_PROCESS KimAct
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
    RANGE C1, C2, C3, C4, C5, alpha, alpha1, alpha2, alpha3, beta, gamma
    RANGE movdep, lengdiv, onset, Afloor, unity, zero, use_ports, rest
    RANGE A, alpha_t, Ainf, tauA, atil0, asw, ssw, tstep
    POINTER caspt, xm, vm, T0, phi1, phi2, xopt, tauA_gain, C1_shift
    RANGE T0c, phi1c, phi2c, xoptc
}

UNITS {
    (M) = (1/liter)
}

PARAMETER {
    unity = 1 (1)
    zero = 0 (1)
    use_ports = 0 (1)
    rest = 1 (1)
    variable_step = 0 (1)
}

ASSIGNED {
    dt (ms)
    tstep (ms)
    caspt (M)
    T0 (M)
    phi1 (/mm)
    phi2 (1)
    xopt (mm)
    xm (mm)
    vm (mm/s)
}

INCLUDE "kim_m2_activation.inc"
INCLUDE "fixed_step.inc"

INITIAL {
    act_initial(caspt, xm, vm)
    tstep = t
}

BREAKPOINT {
    SOLVE states METHOD euler
}

DERIVATIVE states {
    LOCAL nst
    if (variable_step) {
        : the movement clock runs from just after the onset: CVODE stops there (an event), and the step that
        : ends at the onset (whose implicit corrector evaluates this block at t = onset itself) still runs
        : without eqs 19-20, as the continuous model does; the restart at the onset then runs with them
        act_rates(caspt)
        kAd = kA
        activation(t, 1, xm, vm)
    } else {
        : the state is advanced here (act_step): nothing is left for METHOD euler to add
        : the whole step (dt is halved in this block under secondorder: fixed_step.inc)
        nst = euler_steps(t, tstep, dt)
        act_step(dt*nst, caspt, xm, vm)
        kAd = 0
    }
    tstep = t
    atil' = (Ainf - atil)*kAd
}
