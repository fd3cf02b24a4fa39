TITLE MnNoise: independent synaptic noise on a motoneuron, a fluctuating conductance

COMMENT
The part of a motoneuron's synaptic input that no other cell shares (neuromuscle.pool: PoolDefinition's
synaptic_noise_uS): a conductance g (uS) with reversal e (0 mV, excitatory), an Ornstein-Uhlenbeck process of
mean 0, standard deviation sigma (uS) and correlation time tau (ms), as in the point-conductance model of
synaptic bombardment (Destexhe, Rudolph, Fellous & Sejnowski 2001):

    i = g (v - e)                                                   (nA)
    g(t + h) = g(t) exp(-h/tau) + sigma sqrt(1 - exp(-2 h/tau)) N(0, 1)

The update is the process's exact transition over h, so its statistics do not depend on the time step.  It is made
every ``nstep`` fixed steps (h = nstep dt, the multiple of dt nearest ``update``, 0.1 ms by default, and g held
between: a normal draw costs more than a reduced cell's step, and a correlation time of ms needs no finer grid);
the variable-step integrator cannot take it (the pool refuses).
Each instance draws from its own Random123 stream (RANDOM rng; the pool sets its ids from the seed and the unit's
gid) and restarts it at every finitialize, so a run is the same when replayed and on any number of ranks and
threads.  The common drive carries the mean; this process carries the fluctuation of each cell's own inputs
around it.
ENDCOMMENT

NEURON {
    POINT_PROCESS MnNoise
    NONSPECIFIC_CURRENT i
    RANGE sigma, tau, e, update, g, i
    RANDOM rng
    THREADSAFE
}

UNITS {
    (nA) = (nanoamp)
    (mV) = (millivolt)
    (uS) = (microsiemens)
}

PARAMETER {
    sigma = 0 (uS)
    tau = 5 (ms)
    e = 0 (mV)
    update = 0.1 (ms)
}

ASSIGNED {
    dt (ms)
    v (mV)
    i (nA)
    g (uS)
    decay (1)
    spread (1)
    nstep (1)
    count (1)
}

INITIAL {
    random_setseq(rng, 0)
    nstep = floor(update / dt + 0.5)
    if (nstep < 1) {
        nstep = 1
    }
    decay = exp(-nstep * dt / tau)
    spread = sqrt(1 - decay * decay)
    count = 0
    g = sigma * random_normal(rng)
}

BEFORE BREAKPOINT {
    count = count + 1
    if (count >= nstep) {
        count = 0
        g = g * decay + sigma * spread * random_normal(rng)
    }
}

BREAKPOINT {
    i = g * (v - e)
}
