"""The reduced motoneuron: size principle across S, FR, FF; AHP by type; f-I slope; PIC hysteresis."""

import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool.excitability import (ahp_duration_ms, fi_slope_Hz_per_nA, rheobase_nA,
                                           triangle_hysteresis)
from neuromuscle.pool.motoneuron import Motoneuron, motoneuron_parameters, unit_type_of

SIZES = {"S": 0.0, "FR": 0.4, "FF": 1.0}


@pytest.fixture(scope="module")
def rheobases():
    out = {}
    for t, x in SIZES.items():
        with Motoneuron(motoneuron_parameters(x, unit_type=t)) as mn:
            out[t] = rheobase_nA(mn, upper_nA=40.0, tolerance_nA=0.1)
    return out


def test_rheobase_follows_size_S_FR_FF(rheobases):
    assert rheobases["S"] < rheobases["FR"] < rheobases["FF"]
    assert rheobases["FF"] > 3 * rheobases["S"]


def test_input_resistance_falls_with_size():
    rin = []
    for x in SIZES.values():
        with Motoneuron(motoneuron_parameters(x)) as mn:
            rin.append(mn.input_resistance_MOhm())
    assert rin[0] > rin[1] > rin[2] > 0.3
    assert 1.5 < rin[0] < 6.0  # cat S cells: a few MOhm


def test_ahp_lasts_longer_in_S_than_FF():
    with Motoneuron(motoneuron_parameters(0.0)) as s:
        ahp_s = ahp_duration_ms(s)
    with Motoneuron(motoneuron_parameters(1.0)) as ff:
        ahp_ff = ahp_duration_ms(ff)
    assert ahp_s > 1.5 * ahp_ff
    assert 40.0 < ahp_ff < ahp_s < 500.0


def test_fi_slope_is_positive_and_physiological(rheobases):
    with Motoneuron(motoneuron_parameters(1.0)) as ff:
        slope, rates = fi_slope_Hz_per_nA(ff, [1.5 * rheobases["FF"], 2.0 * rheobases["FF"]], duration_ms=700.0,
                                          skip_ms=300.0)
    assert rates[1] > rates[0] > 5.0
    assert 0.5 < slope < 30.0  # cat motoneurons: about 1-10 Hz/nA in the primary range


def test_pic_gives_hysteresis_on_a_triangle():
    # a triangle to 2.5 rheobase (4.6 nA without the PIC), 5 s each way
    with Motoneuron(motoneuron_parameters(0.0)) as mn:
        with_pic = triangle_hysteresis(mn, 11.5, rise_ms=5000.0)
    with Motoneuron(motoneuron_parameters(0.0, neuromodulation=0.0)) as mn:
        no_pic = triangle_hysteresis(mn, 11.5, rise_ms=5000.0)
    assert with_pic.delta_nA < 0.0  # fires on below its recruitment current
    assert no_pic.delta_nA > 0.0    # without the PIC, adaptation: derecruited above recruitment
    assert with_pic.on_nA < no_pic.on_nA


@pytest.mark.parametrize("channels", ["fused", "separate"])
def test_a_distal_pic_keeps_its_total_and_its_hysteresis(channels):
    import numpy as np

    from neuron import h

    uniform = motoneuron_parameters(0.0)
    distal = motoneuron_parameters(0.0, pic_start_x=1.0 / 3.0, dend_nseg=6)
    mech = "mn_pic" if channels == "fused" else "mn_cal"
    with Motoneuron(distal, channels=channels) as mn:
        g = np.array([getattr(seg, mech).gbar for seg in mn.dend])
        area = np.array([h.area(seg.x, sec=mn.dend) for seg in mn.dend])
        assert np.all(g[:2] == 0.0) and np.all(g[2:] > uniform.g_pic_S_per_cm2)
        assert (g * area).sum() == pytest.approx(uniform.g_pic_S_per_cm2 * area.sum(), rel=1e-12)
        assert triangle_hysteresis(mn, 11.5, rise_ms=5000.0).delta_nA < 0.0   # still fires on below recruitment
    with Motoneuron(uniform, channels=channels) as mn:
        assert all(getattr(seg, mech).gbar == uniform.g_pic_S_per_cm2 for seg in mn.dend)


def test_axon_delay_and_types():
    s, ff = motoneuron_parameters(0.0), motoneuron_parameters(1.0)
    assert s.axon_delay_ms > ff.axon_delay_ms > 0
    assert motoneuron_parameters(0.5, axon_length_mm=900.0).axon_delay_ms == pytest.approx(
        900.0 / motoneuron_parameters(0.5).conduction_m_per_s)
    assert [unit_type_of(x) for x in (0.1, 0.3, 0.9)] == ["S", "FR", "FF"]
    assert unit_type_of(0.9, (1.0, 0.0, 0.0)) == "S"


@pytest.mark.parametrize("bad", [dict(size=1.5), dict(size=float("nan")), dict(size=0.2, soma_diam_um=-3.0),
                                 dict(size=0.2, unit_type="X"), dict(size=0.2, nonsense=1.0),
                                 dict(size=0.2, pic_start_x=1.0), dict(size=0.2, pic_start_x=-0.1)])
def test_bad_parameters_are_refused(bad):
    size = bad.pop("size")
    with pytest.raises(InputError):
        motoneuron_parameters(size, **bad)


def test_scales_multiply_size_dependent_parameters_only():
    base, slow = motoneuron_parameters(0.3), motoneuron_parameters(0.3, scales={"ca_decay_ms": 2.0})
    assert slow.ca_decay_ms == pytest.approx(2.0 * base.ca_decay_ms) and slow.soma_diam_um == base.soma_diam_um
    with pytest.raises(InputError, match="only size-dependent"):
        motoneuron_parameters(0.3, scales={"ek_mV": 2.0})


def _rates_over_time(size, amp_factor=1.5, **overrides):
    """Mean rate (Hz) in the first and the last 2 s of an 8-s step at amp_factor x rheobase (no PIC)."""
    import numpy as np

    from neuromuscle.pool.excitability import clamp_run

    with Motoneuron(motoneuron_parameters(size, neuromodulation=0.0, **overrides)) as mn:
        rb = rheobase_nA(mn, upper_nA=80.0, tolerance_nA=0.2)
        sp, _ = clamp_run(mn, [0.0], [amp_factor * rb], 8000.0, steps=True)
    def rate(a, b):
        s = sp[(sp >= a) & (sp < b)]
        return (s.size - 1) * 1000.0 / (s[-1] - s[0])

    return rate(500.0, 2500.0), rate(6000.0, 8000.0), np.asarray(sp)


def test_late_adaptation_slows_a_steady_discharge_the_faster_cell_more():
    ks = dict(g_ks_S_per_cm2=0.1, ks_tau_ms=2000.0)
    with Motoneuron(motoneuron_parameters(0.0)) as mn:        # off by default: no mechanism inserted
        assert not hasattr(mn.soma(0.5), "mn_ks")
    s_early, s_late, _ = _rates_over_time(0.0, **ks)
    f_early, f_late, _ = _rates_over_time(1.0, **ks)
    s_bare_early, s_bare_late, _ = _rates_over_time(0.0)
    assert abs(s_bare_late - s_bare_early) < 0.2            # without it the discharge holds its rate
    assert s_late < s_early - 0.5 and f_late < f_early - 0.5
    assert f_early - f_late > s_early - s_late              # the faster (FF) cell adapts more in Hz
    with Motoneuron(motoneuron_parameters(0.0, **ks), channels="separate") as mn:   # the reference channels too
        assert mn.soma(0.5).mn_ks.gbar == 0.1 and mn.soma(0.5).mn_ks.mtau == 2000.0


def test_command_line_settings_name_their_fault():
    from neuromuscle.pool.motoneuron import parse_settings

    assert parse_settings(["cal_vhalf_mV=-52", " g_ks_S_per_cm2 = 0.03"]) == {"cal_vhalf_mV": -52.0,
                                                                             "g_ks_S_per_cm2": 0.03}
    for bad, said in (("cal_vhalf_mV", "NAME=VALUE"), ("vhalf=-52", "no parameter 'vhalf'"),
                      ("cal_vhalf_mV=low", "not a number"), ("neuromodulation=0.8", "its own option")):
        with pytest.raises(InputError, match=said):
            parse_settings([bad])


def test_a_gate_slope_must_be_positive():
    for name in ("cal_slope_mV", "km_slope_mV"):
        with pytest.raises(InputError, match=name):
            motoneuron_parameters(0.0, **{name: 0.0})
    assert motoneuron_parameters(0.0, km_vhalf_mV=-60.0).km_vhalf_mV == -60.0   # a half-activation may be < 0


def test_a_synaptic_drive_outlives_the_callers_time_vector():
    import gc

    from neuron import h

    from neuromuscle.pool.excitability import clamp_run

    with Motoneuron(motoneuron_parameters(0.0)) as mn:
        kept = mn.play_synaptic_conductance(h.Vector([0.0]), [0.3])   # the time Vector is not kept by the caller
        gc.collect()
        spikes, _ = clamp_run(mn, [0.0, 500.0], [0.0, 0.0], 500.0, steps=True)
        for vec in kept:
            vec.play_remove()
    assert spikes.size > 3
