TITLE IbInterneuron: the leaky integrate-and-fire interneuron of the Ib inhibitory pathway

COMMENT
The interneuron between Golgi tendon organ (Ib) afferents and the motoneurons of the stretch-reflex loop
(neuromuscle.pool.reflex): an artificial leaky integrator of the afferent's spikes, in the manner of NEURON's
IntFire1 (whose compiled form CoreNEURON does not carry), so that NEURON and CoreNEURON run the same loop.

    m(t) = m(t0) exp(-(t - t0)/tau)        between inputs (m dimensionless, t in ms)
    m -> m + w                              at an input spike of NetCon weight w (1)

When m exceeds 1 the cell fires (net_event), m is reset to 0 and inputs are ignored for refrac (ms).
Units: tau, refrac in ms; m and the weights in units of the threshold (1).
ENDCOMMENT

NEURON {
    ARTIFICIAL_CELL IbInterneuron
    THREADSAFE
    RANGE tau, refrac, m
}

PARAMETER {
    tau = 10 (ms)
    refrac = 1 (ms)
}

ASSIGNED {
    m (1)
    t0 (ms)
    refractory (1)
}

INITIAL {
    m = 0
    t0 = t
    refractory = 0
}

NET_RECEIVE(w (1)) {
    if (flag == 1) {
        refractory = 0
        m = 0
        t0 = t
    } else if (refractory == 0) {
        m = m*exp(-(t - t0)/tau) + w
        t0 = t
        if (m > 1) {
            refractory = 1
            m = 0
            net_send(refrac, 1)
            net_event(t)
        }
    }
}
