TITLE Kim, Sandercock & Heckman 2015, Module 3: activation to force, Hill/Mashima CE and series elastic element (KimForce)

COMMENT
Module 3 of the three-module muscle of Kim, Sandercock & Heckman 2015: activation -> force, a Hill/Mashima
contractile element (CE) in series with a linear series elastic element (SE).

Equations: eqs 9-12 of the paper, written once in kim_m3_force.inc (shared with the fused KimUnit):
    F  = P0 KSE (dXm - dXCE), F = 0 where dXm - dXCE <= 0                      (eq 9)
    Fc = P0 g(Xm) A,  g(Xm) = exp(-((Xm - g1)/g2)^2)                          (eq 12)
    F <= Fc (shortening, Hill):     dXCE/dt = -b0 (Fc - F)/(F + a0 Fc/P0)      (eq 10)
    F >  Fc (lengthening, Mashima): dXCE/dt = -d0 (Fc - F)/(2 Fc - F + c0 Fc/P0) (eq 11)
Here XCE starts at the initial muscle length, so dXm - dXCE = Xm - XCE and the reference lengths cancel
(both references start at the trial's length).
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
activated unit at a ramp's onset (0.009 % with dxce).  |dxce| is of the order of the SE's
extension plus the length change, so rtol now acts on the force's own scale.

Two more fixed-step rules (both O(1) per step; isometric and shortening trials of the published sets never meet
them, so their numbers are unchanged):
- error control: after the step, its local error is estimated as k h |v(start) - v(end)|/2 (N, the first-order
  term) and, above subtol (1e-3) times the force's scale max(F, Fc), the step is redone as n = 1 + floor(err/
  (subtol scale)) substeps (at most nsubmax = 64; nsubmax = 1 turns it off) along the length interpolated from
  the previous step's, and with the activation interpolated likewise from the previous step's A (held at the
  step's end's A over every substep, a regenerative twitch's fall, where F follows eq 11's asymptote as A
  collapses, is 1.1 % of peak off; 0.6 % interpolated), except where KimAct reports ssw = -1 (the movement
  onset's step, where A jumps: interpolating there is 2.6 % off) (RANGE nsub counts them).  A fast transient
  needs it: at low activation the CE-SE loop settles within a fraction of a step when A jumps (2.8 -> 0.25 % of
  peak), and a weak unit's SE taking up slack loads in ~0.01 ms (1.23 % of a 0.0018 N peak with at most 16
  substeps, whose backward-Euler error on that transient remains; 0.28 % with 64).  The cap bounds the cost of the rare steps
  that need it; random length's cost did not change measurably.
- eq 20's switch within the step: KimAct reports where in the step (ssw, a fraction) the lengthening-below-the-
  optimum condition starts or stops holding and the activation before it (asw); the step is then taken in two
  parts, asw over ssw dt and A over the rest (RANGE nsplit counts them): holding A of the step's end over the
  whole step errs by 1.6 % of peak where Xm crosses the optimum in a 200 mm/s ramp, the split by 0.3 %.  POINTER asw,
  ssw are read only when use_split = 1 (the Python wiring sets it when they point at KimAct's asw, ssw); with
  use_split = 0 (default: an excitation model without eq 20) the step is not split and they need not be set.

Coupling: POINTER act -> activation A (1) of an excitation mechanism (KimAct, or any model exposing A);
          POINTER xm   -> muscle length (mm) of a MuscleLength point process;
          POINTER force_offset -> modulation port (N): a history-dependent element in parallel with the CE-SE
                   (force enhancement after stretch, depression after shortening) adds force_offset to the
                   output F = Fse + force_offset; the CE-SE dynamics see Fse only.  Read only when use_ports = 1
                   (set by the Python wiring, which points it at RANGE zero when unused), else 0.
          POINTER capacity_gain -> modulation port (1): multiplies the force capacity, Fc = P0 g(Xm) A capacity_gain
                   (a loss of force per cross-bridge, as in fatigue); read only when use_ports = 1 (pointed at
                   RANGE unity when unused), else 1.
Numerics: fixed step: one linearly implicit (Rosenbrock-Euler) step with the exact dv/dF (L-stable for the
stiff SE-CE loop at low activation); F and vce are then recomputed from the updated XCE, so the fixed step
reports the force at the step's end (as CVODE does), not at its start; CVODE (variable_step = 1): exact
right-hand side written a - b XCE (see KimCa).
ENDCOMMENT

NEURON {
    POINT_PROCESS KimForce
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
    RANGE P0, KSE, g1, g2, a0, b0, c0, d0, vmax, asym, lincurv, fcmin, F0, zero, unity, use_ports, use_split, rest
    RANGE F, Fse, Fc, vce, nasym, xce, x0, subtol, nsubmax, nsub, nsplit, tstep
    POINTER act, xm, force_offset, capacity_gain, asw, ssw
}

PARAMETER {
    zero = 0 (N)
    unity = 1 (1)
    use_ports = 0 (1)
    use_split = 0 (1)
    rest = 1 (1)
    variable_step = 0 (1)
}

ASSIGNED {
    dt (ms)
    tstep (ms)
    act (1)
    xm (mm)
    asw (1)
    ssw (1)
}

INCLUDE "kim_m3_force.inc"
INCLUDE "fixed_step.inc"

INITIAL {
    xl = xm
    al = act
    read_capacity()
    ce_initial()
    tstep = t
}

BREAKPOINT {
    SOLVE states METHOD euler
    if (!variable_step) {
        : fixed step: report F and vce of the updated CE state (the DERIVATIVE block's are the step's start)
        xl = xm
        al = act
        read_capacity()
        ce_report()
    }
}

DERIVATIVE states {
    LOCAL nst
    : the POINTERs are read once per evaluation into xl, al
    xl = xm
    al = act
    read_capacity()
    if (variable_step) {
        ce_rhs()
    } else {
        sw = 0
        if (use_split) {
            sw = ssw
        }
        : the whole step (dt is halved in this block under secondorder: fixed_step.inc)
        nst = euler_steps(t, tstep, dt)
        ce_fixed_step(dt*nst)
        aa = acs
        bb = 0
    }
    tstep = t
    dxce' = aa - bb*dxce
    se_force()
}
