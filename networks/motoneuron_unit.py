"""A motoneuron drives its muscle unit inside NEURON: HH soma -> NetCon -> KimCa -> KimAct -> KimForce.

Run: python networks/motoneuron_unit.py  (prints the spike count and peak force; writes motoneuron_unit.png)
Units: ms, mV, nA, mm, N.
"""

import numpy as np
from neuron import h

from neuromuscle import MuscleUnit, load_parameters
from neuromuscle.unit import _NeuronRun


def main(current_nA: float = 2.0, duration_ms: float = 1500.0) -> None:
    soma = h.Section(name="motoneuron")
    soma.L = soma.diam = 50.0
    soma.insert("hh")
    drive = h.IClamp(soma(0.5))
    drive.delay, drive.dur, drive.amp = 200.0, 1000.0, current_nA
    with MuscleUnit(load_parameters("CT09"), name="mu") as unit:
        unit.length.xm = -8.0
        nc = unit.connect_from(soma(0.5)._ref_v, section=soma, threshold_mV=0.0, delay_ms=5.0)
        t, f = h.Vector().record(h._ref_t, 0.5), h.Vector().record(unit.force._ref_F, 0.5)
        with _NeuronRun("fixed", 0.025, 0, 0) as hh:
            hh.finitialize(-65.0)
            hh.continuerun(duration_ms)
        print(f"{int(unit.ca.nspike)} spikes, peak force {np.array(f).max():.2f} N")
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        plt.plot(np.array(t), np.array(f))
        plt.xlabel("time (ms)")
        plt.ylabel("force (N)")
        plt.savefig("motoneuron_unit.png", dpi=90)
        del nc


if __name__ == "__main__":
    main()
