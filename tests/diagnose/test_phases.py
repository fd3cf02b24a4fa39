"""Trial descriptions: stimulation, holds and ramps, the holds after a movement, the isometric phases of moving
trials, and the facts the causes ask of a trial."""

import numpy as np
import pytest

from neuromuscle.diagnose.phases import describe, stimulated_mask
from neuromuscle.measured import Trial
from neuromuscle.protocols import isokinetic_ramp


def _trial(stim_s, length=None, duration_s=3.0, tid="t", protocol="train", sample_s=0.001, x0=-8.0):
    t = np.arange(int(round(duration_s / sample_s)) + 1) * sample_s
    return Trial(trial_id=tid, protocol=protocol, time_s=t, force=np.zeros_like(t), force_unit="N",
                 length_unit="mm", length_const=None if length is not None else x0,
                 length=None if length is None else length(t), stimulus_times_s=np.asarray(stim_s, dtype=float))


def _ramp(x_from, x_to, speed, start_s, duration_s=3.0):
    law = isokinetic_ramp(x_from, x_to, speed, start_s * 1000.0, duration_s * 1000.0)
    return lambda t: law.at(t * 1000.0)


def test_isometric_train_facts():
    ph = describe(_trial(0.1 + np.arange(20) / 20.0))
    assert ph.isometric_length_mm == -8.0 and not ph.moves and not ph.active_movement
    assert ph.n_stimuli == 20 and ph.regular_rate_hz == pytest.approx(20.0)
    assert ph.mean_rate_hz == pytest.approx(20.0) and ph.min_isi_ms == pytest.approx(50.0)
    assert ph.train_s == pytest.approx(0.95) and not ph.burst_after_pause
    assert [p.kind for p in ph.phases] == ["hold"] and ph.movement_kind == "isometric"
    assert ph.isometric_stimulated().sum() == ph.stimulated.sum() > 0
    assert ph.length_offset_mm(-6.0) == pytest.approx(-2.0)


def test_stimulation_mask_leaves_out_pauses_between_bursts():
    t = np.arange(3001) * 0.001
    stim = np.concatenate([0.1 + np.arange(10) * 0.01, 1.5 + np.arange(10) * 0.01])
    m = stimulated_mask(t, stim)
    assert m[150] and not m[800] and m[1550] and not m[2500]


def test_stretch_hold_has_a_ramp_then_a_hold_after_it():
    stim = 0.1 + np.arange(100) / 40.0
    ph = describe(_trial(stim, _ramp(-8.0, -3.0, 20.0, 0.6)))
    kinds = [p.kind for p in ph.phases]
    assert kinds == ["hold", "ramp", "hold"] and ph.phases[1].sign == 1
    assert ph.phases[1].velocity_mm_s == pytest.approx(20.0, rel=0.05)
    after = ph.hold_after(1)
    ramp_end = ph.phases[1].end_s
    assert after.any() and ph.time_s[after].min() > ramp_end + 0.2 - 1e-9
    assert not ph.hold_after(-1).any()  # no shortening
    iso = ph.isometric_stimulated()  # the hold before the ramp, and the hold 0.2 s after it
    assert iso[int(0.3 / 0.001)] and not iso[int(0.7 / 0.001)] and iso[int(1.5 / 0.001)]
    assert ph.active_movement and ph.isometric_length_mm is None and ph.movement_kind == "ramps"


def test_a_movement_that_is_not_a_ramp_and_lengthening_below_the_optimum():
    stim = 0.1 + np.arange(40) / 10.0
    ph = describe(_trial(stim, lambda t: -8.0 + 3.0 * np.sin(2 * np.pi * 0.5 * t), duration_s=4.0))
    assert any(p.kind == "movement" for p in ph.phases) and ph.movement_kind == "movement"
    assert ph.lengthening_below(-6.0) and not ph.lengthening_below(-20.0)
    assert not ph.hold_after(1).any()  # brief stops of a sinusoid are not holds


def test_a_movement_of_the_passive_muscle_leaves_a_trial_isometric_in_kind():
    """Stimulated only after a passive stretch: a kind of movement is how the length moves while stimulated."""
    stim = 1.5 + np.arange(20) / 20.0
    ph = describe(_trial(stim, _ramp(-8.0, -3.0, 20.0, 0.2)))
    assert ph.moves and not ph.active_movement and ph.movement_kind == "isometric"


def test_burst_after_pause_and_irregular_rates():
    stim = np.concatenate([0.1 + np.arange(3.0), 3.1 + np.arange(30) * 0.01, 3.7 + np.arange(4) * 2.0])
    ph = describe(_trial(stim, duration_s=12.0))
    assert ph.burst_after_pause and ph.regular_rate_hz == 0.0
    doublet = describe(_trial(np.sort(np.concatenate([0.1 + np.arange(10) / 10.0, [0.108]]))))
    assert doublet.min_isi_ms == pytest.approx(8.0) and doublet.max_isi_ms >= 2 * doublet.min_isi_ms
