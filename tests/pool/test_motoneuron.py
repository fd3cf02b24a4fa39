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


def test_axon_delay_and_types():
    s, ff = motoneuron_parameters(0.0), motoneuron_parameters(1.0)
    assert s.axon_delay_ms > ff.axon_delay_ms > 0
    assert motoneuron_parameters(0.5, axon_length_mm=900.0).axon_delay_ms == pytest.approx(
        900.0 / motoneuron_parameters(0.5).conduction_m_per_s)
    assert [unit_type_of(x) for x in (0.1, 0.3, 0.9)] == ["S", "FR", "FF"]
    assert unit_type_of(0.9, (1.0, 0.0, 0.0)) == "S"


@pytest.mark.parametrize("bad", [dict(size=1.5), dict(size=float("nan")), dict(size=0.2, soma_diam_um=-3.0),
                                 dict(size=0.2, unit_type="X"), dict(size=0.2, nonsense=1.0)])
def test_bad_parameters_are_refused(bad):
    size = bad.pop("size")
    with pytest.raises(InputError):
        motoneuron_parameters(size, **bad)


def test_scales_multiply_size_dependent_parameters_only():
    base, slow = motoneuron_parameters(0.3), motoneuron_parameters(0.3, scales={"ca_decay_ms": 2.0})
    assert slow.ca_decay_ms == pytest.approx(2.0 * base.ca_decay_ms) and slow.soma_diam_um == base.soma_diam_um
    with pytest.raises(InputError, match="only size-dependent"):
        motoneuron_parameters(0.3, scales={"ek_mV": 2.0})
