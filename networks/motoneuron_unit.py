"""A motoneuron drives its muscle unit inside NEURON: HH soma -> NetCon -> KimCa -> KimAct -> KimForce.

Run: python networks/motoneuron_unit.py [OUT.png]  (prints the spike count and peak force; writes the figure)
Units: ms, mV, nA, mm, N.
"""

import sys

import numpy as np
from neuron import h

from neuromuscle import MuscleUnit, Simulator, load_parameters
from neuromuscle.reports.figures import label_axes, new_figure, save_figure, set_title


def main(current_nA: float = 2.0, duration_ms: float = 1500.0, png: str = "motoneuron_unit.png") -> float:
    """Run the example; returns the peak force (N)."""
    soma = h.Section(name="motoneuron")
    soma.L = soma.diam = 50.0
    soma.insert("hh")
    drive = h.IClamp(soma(0.5))
    drive.delay, drive.dur, drive.amp = 200.0, 1000.0, current_nA
    with MuscleUnit(load_parameters("CT09"), name="mu") as unit:
        unit.length.xm = -8.0
        nc = unit.connect_from(soma(0.5)._ref_v, section=soma, threshold_mV=0.0, delay_ms=5.0)
        f = h.Vector().record(unit.ref("force.F"), 0.5)
        Simulator(method="fixed", dt_ms=0.025, v_init_mV=-65.0).run(duration_ms)
        force = np.array(f)
        peak = float(force.max())
        print(f"{int(unit['ca'].obj.nspike)} spikes, peak force {peak:.2f} N")
        fig, (ax,) = new_figure(1)
        ax.plot(np.arange(force.size) * 0.5, force, "k")
        label_axes(ax, x="time (ms)", y="force (N)")
        set_title(ax, f"HH motoneuron, {current_nA:g} nA step -> CT09 muscle unit")
        save_figure(fig, png)
        del nc
    return peak


if __name__ == "__main__":
    main(png=sys.argv[1] if len(sys.argv) > 1 else "motoneuron_unit.png")
