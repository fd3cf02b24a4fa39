TITLE Kim, Sandercock & Heckman 2015, Module 1: spikes to Ca2+ in the SR and sarcoplasm (KimCa)

COMMENT
Module 1 of the three-module muscle of Kim, Sandercock & Heckman 2015: spikes -> Ca2+ in the SR and sarcoplasm.

Equations: eqs 1-7 of the paper, the cooperativity K6 = K6i/(1 + 5 Atil) and the length compensation eq 18
(K5 = phi(Xm) K5i when lencomp = 1), written once in kim_m1_calcium.inc (shared with the fused KimUnit).
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
Registration order: NEURON advances mechanisms in the order their files are registered (by file name): this
file's name keeps Module 1 before Module 2 (kim_m2_activation.mod) and Module 3 (kim_m3_force.mod).

Numerics.  Fixed step: one linearly implicit (Rosenbrock-Euler) step of the five coupled Ca states with the
exact analytic Jacobian, solved by eliminating CaSRCS, CaSPB and CaSPT into a 2x2 system; the kernels decay
exactly and R uses their exact average over the step.  K6's cooperativity reads Atil extrapolated to the step's
middle from its last two values (KimAct advances after this mechanism): with Atil of the step's start the loop
CaSPT -> Atil -> K6 lags by a step, and a regenerative twitch can be missed.  L-stable, no Newton iteration, no
history loop.
Variable step (CVODE, variable_step = 1): the DERIVATIVE block gives the exact right-hand side, written a - b*y so
that CVODE's diagonal Jacobian approximation sees the stiff terms.  In fixed step a holds the step's increment / dt
and b = 0, so METHOD euler applies exactly that increment.
ENDCOMMENT

NEURON {
    POINT_PROCESS KimCa
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
    RANGE K1, K2, K3, K4, K5i, K6i, K, Rmax, Umax, tau1, tau2, CS0, B0, T0, CaSR0
    RANGE phi1, phi2, phi3, phi4, xopt, lencomp
    RANGE R, U, K5, K6, phi, nspike, unity, use_ports, rest, tstep
    POINTER atil, xm, release_gain, uptake_gain
}

UNITS {
    (M) = (1/liter)
}

PARAMETER {
    unity = 1 (1)
    use_ports = 0 (1)
    rest = 1 (1)
    variable_step = 0 (1)
}

ASSIGNED {
    dt (ms)
    tstep (ms)
    atil (1)
    xm (mm)
}

INCLUDE "kim_m1_calcium.inc"
INCLUDE "fixed_step.inc"

INITIAL {
    ca_initial(atil, xm)
    tstep = t
}

BREAKPOINT {
    SOLVE states METHOD euler
}

DERIVATIVE states {
    LOCAL nst
    if (variable_step) {
        ca_rhs(atil, xm)
    } else {
        : the whole step (dt is halved in this block under secondorder: fixed_step.inc)
        nst = euler_steps(t, tstep, dt)
        ca_step(dt*nst, atil, xm)
    }
    tstep = t
    CaSR' = a1 - b1*CaSR
    CaSRCS' = a2 - b2*CaSRCS
    CaSP' = a3 - b3*CaSP
    CaSPB' = a4 - b4*CaSPB
    CaSPT' = a5 - b5*CaSPT
    S2' = a6 - b6*S2
    S12' = a7 - b7*S12
}

