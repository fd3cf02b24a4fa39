"""Both engines integrate the same fixed step: CoreNEURON (mechanisms compiled by nrnivmodl-core into the same
content-keyed cache) gives a unit's traces bit for bit as NEURON does, the three modules and the fused KimUnit,
isometric and under a played length with the movement compensations; CoreNEURON refuses what it cannot do."""

import numpy as np
import pytest

from neuromuscle import InputError, kim_excitation, simulate
from neuromuscle.model import kim_fused, mechanisms
from neuromuscle.protocols import random_length
from neuromuscle.sim import Simulator

CORE = Simulator(engine="coreneuron")


def test_coreneuron_build_is_cached_beside_neurons():
    lib = mechanisms.coreneuron_library()
    assert lib.name == "libcorenrnmech.so" and lib == mechanisms.coreneuron_library()
    assert lib.parent.parent.name.endswith("-core")
    assert lib.parent.parent.name.removesuffix("-core") == mechanisms.compiled_library().parent.parent.name


@pytest.mark.parametrize("fused", [False, True], ids=["modules", "fused"])
@pytest.mark.parametrize("movement", [False, True], ids=["static", "movement_compensation"])
def test_coreneuron_gives_neurons_traces_bit_for_bit(ct09, fused, movement):
    trace = random_length(600.0, seed=3)
    spikes = list(30.0 + 25.0 * np.arange(20))
    exc = kim_fused(True, movement) if fused else kim_excitation(True, movement)
    slot = "muscle" if fused else "force"
    record = [f"{slot}.F", f"{'muscle' if fused else 'act'}.A", f"{'muscle' if fused else 'ca'}.CaSPT"]
    a = simulate(ct09, spikes, trace, 600.0, excitation=exc, record=record)
    b = simulate(ct09, spikes, trace, 600.0, excitation=exc, record=record, simulator=CORE)
    assert a[f"{slot}.F"].max() > 1.0 and b.t_ms.size == a.t_ms.size
    for name in record:
        np.testing.assert_array_equal(b[name], a[name], err_msg=name)
    assert b.settings["engine"] == "coreneuron" and "engine" not in a.settings


def test_coreneuron_takes_no_variable_step():
    with pytest.raises(InputError, match="fixed step only"):
        Simulator(method="cvode", engine="coreneuron")
    with pytest.raises(InputError, match="engine must be one of"):
        Simulator(engine="gpu")


def test_a_neuron_run_after_a_coreneuron_run_is_unchanged(ct09):
    """The Simulator puts back what it set for CoreNEURON: NEURON runs on as before in the same process."""
    from neuron import coreneuron

    before = simulate(ct09, [20.0, 60.0], -8.0, 200.0)["force.F"]
    simulate(ct09, [20.0, 60.0], -8.0, 200.0, simulator=CORE)
    assert not coreneuron.enable
    np.testing.assert_array_equal(simulate(ct09, [20.0, 60.0], -8.0, 200.0)["force.F"], before)
