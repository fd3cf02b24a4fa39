"""The reduced motoneuron against published cat and human motoneuron figures: input resistance, rheobase, AHP,
f-I slopes (primary and secondary ranges), rate saturation under a common synaptic drive, Delta F and
self-sustained firing set by the neuromodulation parameter.

Published ranges (means +- about 2 SD of the cited samples, widened where studies differ):
- cat medial gastrocnemius (Zengel, Reid, Sypert & Munson 1985): input resistance S 1.6 +- 0.5, FF 0.6 +- 0.2
  MOhm; rheobase S 5 +- 2, FF 21 +- 8 nA; AHP duration S 161, FF 65 ms; lumbar cells span 0.5-5 MOhm
  (Gustafsson & Pinter 1984);
- f-I slope of the steady discharge: primary range 1-4 Hz/nA, the secondary range steeper (Kernell 1965;
  Powers & Binder 2001);
- paired-unit Delta F of human motor units 2-7 Hz (Gorassini, Yang, Eken & Bennett 2002; Hassan et al. 2020);
- bistability (firing outlasting a brief pulse) with strong monoaminergic drive (Lee & Heckman 1998);
- a minimum steady rate, lower in cells with a longer AHP (Kernell 1965), given by the M-like current.
The cell's input resistance is the one NEURON's 0-Hz impedance gives, checked against a current step here.
"""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import discharge_stats
from neuromuscle.pool.excitability import (ahp_duration_ms, clamp_run, fi_slope_Hz_per_nA,
                                           input_resistance_step_MOhm, minimum_synaptic_rate, rheobase_nA,
                                           self_sustained_ms, synaptic_rates_hz, synaptic_triangle)
from neuromuscle.pool.motoneuron import HUMAN_NEUROMODULATION, Motoneuron, motoneuron_parameters

S, FF = 0.0, 1.0


def _cell(size, neuromodulation=0.0):
    return Motoneuron(motoneuron_parameters(size, neuromodulation=neuromodulation))


@pytest.fixture(scope="module")
def rheobases():
    out = {}
    for x in (S, FF):
        with _cell(x) as mn:
            out[x] = rheobase_nA(mn, upper_nA=80.0, tolerance_nA=0.1)
    return out


@pytest.mark.parametrize("size, lo, hi", [(S, 1.0, 3.0), (FF, 0.3, 1.2)])
def test_input_resistance_in_the_cat_range_and_equal_to_a_step(size, lo, hi):
    with _cell(size) as mn:
        rin = mn.input_resistance_MOhm()
        step = input_resistance_step_MOhm(mn)
    assert lo < rin < hi
    assert step == pytest.approx(rin, rel=0.02)


def test_rheobase_in_the_cat_range(rheobases):
    assert 2.0 < rheobases[S] < 9.0
    assert 10.0 < rheobases[FF] < 32.0


@pytest.mark.parametrize("size, lo, hi", [(S, 110.0, 220.0), (FF, 40.0, 90.0)])
def test_ahp_duration_in_the_cat_range(size, lo, hi):
    with _cell(size) as mn:
        assert lo < ahp_duration_ms(mn) < hi


@pytest.mark.parametrize("size", [S, FF])
def test_fi_primary_and_secondary_ranges(size, rheobases):
    rb = rheobases[size]
    with _cell(size) as mn:
        primary, low = fi_slope_Hz_per_nA(mn, [1.25 * rb, 1.5 * rb, 2.0 * rb], 1500.0, 1000.0)
        secondary, high = fi_slope_Hz_per_nA(mn, [3.0 * rb, 4.0 * rb, 5.0 * rb], 1500.0, 1000.0)
    assert np.all(np.diff(np.concatenate([low, high])) > 0)
    assert 1.0 <= primary <= 4.0
    assert primary < secondary <= 4.0 * primary


@pytest.mark.parametrize("size", [S, 0.5, FF])
def test_rates_saturate_under_the_common_synaptic_drive(size):
    g = np.array([0.1, 0.2, 0.4, 0.6, 0.8, 1.0])               # uS: the pools' drive range
    with _cell(size, 0.6) as mn:
        rates = synaptic_rates_hz(mn, g)
    on = rates > 0
    assert on.sum() >= 3 and np.all(on[np.argmax(on):])          # recruited, and firing on to the top
    g, rates = g[on], rates[on]
    assert np.all(np.diff(rates) > 0)                            # no depolarisation block
    slopes = np.diff(rates) / np.diff(g)
    assert slopes[-1] < 0.8 * slopes[0]                          # saturating, not a runaway
    assert rates[-1] < 60.0                                      # human units at MVC: 30-50 Hz


def _triangle_trains(sizes, neuromodulation, peak_nA=14.0, rise_ms=5000.0):
    trains = []
    for x in sizes:
        with _cell(x, neuromodulation) as mn:
            sp, _ = clamp_run(mn, [0.0, rise_ms, 2 * rise_ms], [0.0, peak_nA, 0.0], 2 * rise_ms, steps=False)
        trains.append(sp)
    return trains


def test_delta_f_is_set_by_neuromodulation():
    sizes = [0.0, 0.15, 0.3, 0.45, 0.6]
    modulated = discharge_stats.delta_f(_triangle_trains(sizes, 0.75))
    assert modulated.pairs >= 1
    assert 2.0 <= modulated.median_hz <= 7.0
    bare = discharge_stats.delta_f(_triangle_trains(sizes, 0.0))
    assert not bare.per_test_unit_hz or bare.median_hz < 1.0


def test_synaptic_triangle_hysteresis_is_the_pics():
    # without a PIC a cell stops where it started (its AHP and the drive's rate of change aside); with the
    # human neuromodulation the smallest cells fire on well below their recruitment drive
    sizes = (0.0, 0.3)
    bare = synaptic_triangle(sizes, 0.0, rise_ms=4000.0)
    assert np.all(np.isfinite(bare.on_uS)) and np.allclose(bare.off_uS, bare.on_uS, rtol=0.1)
    modulated = synaptic_triangle(sizes, HUMAN_NEUROMODULATION, rise_ms=4000.0)
    assert modulated.on_uS[0] < bare.on_uS[0]
    assert modulated.off_uS[0] < 0.75 * modulated.on_uS[0]
    assert modulated.summary()["delta_f"]["pairs"] == modulated.delta_f.pairs


def test_self_sustained_firing_with_strong_neuromodulation(rheobases):
    bias = 0.5 * rheobases[S]
    with _cell(S, 1.0) as mn:
        assert self_sustained_ms(mn, bias, rheobases[S]) > 2500.0
    with _cell(S, 0.0) as mn:
        assert self_sustained_ms(mn, bias, rheobases[S]) == 0.0


def test_the_m_current_sets_a_minimum_rate_near_the_inverse_ahp(capsys):
    # with the PIC on and no M current a cell fires ever more slowly as the drive nears threshold; with it the
    # lowest steady rate is near 1000 / AHP duration (ms), as Kernell 1965 found it tied to the AHP
    from neuromuscle.pool.excitability import main

    with _cell(0.3, HUMAN_NEUROMODULATION) as mn:
        inverse_ahp = 1000.0 / ahp_duration_ms(mn)
        _, bare = minimum_synaptic_rate(mn)
    assert bare < 0.5 * inverse_ahp
    with _cell(0.3) as mn:
        for bad in (dict(tolerance=0.0), dict(upper_uS=-1.0)):
            with pytest.raises(InputError, match="minimum_synaptic_rate"):
                minimum_synaptic_rate(mn, **bad)
    rows = main(["--minimum-rate", str(HUMAN_NEUROMODULATION), "--set", "g_km_S_per_cm2=0.002"])
    assert [r["size"] for r in rows] == [0.0, 0.3, 0.6] and '"minimum_rate_hz"' in capsys.readouterr().out
    for r in rows:
        assert r["overrides"] == {"g_km_S_per_cm2": 0.002}
        assert 0.8 * 1000.0 / r["ahp_ms"] <= r["minimum_rate_hz"] <= 1.3 * 1000.0 / r["ahp_ms"]
    assert rows[0]["minimum_rate_hz"] < rows[1]["minimum_rate_hz"] < rows[2]["minimum_rate_hz"]


def test_excitability_command_rejects_a_setting_without_a_value(capsys):
    from neuromuscle.pool.excitability import main

    with pytest.raises(SystemExit):
        main(["--synaptic-triangle", "0.6", "--set", "cal_vhalf_mV"])
    assert "NAME=VALUE" in capsys.readouterr().err
