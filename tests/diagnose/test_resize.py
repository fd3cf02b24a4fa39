"""Rule R8's numbers on constructed forces: a later candidate's held-out gain beyond a resize of the causes named
before it, one size per cause and kind of held-out trial."""

import numpy as np
import pytest

from conftest import ar1
from neuromuscle.diagnose.evidence import WindowSamples, gather
from neuromuscle.diagnose.residuals import noise_level
from neuromuscle.diagnose.resize import beyond_resize
from neuromuscle.diagnose.rules import MIN_BEYOND_RESIZE, apply_rules

N = 800
T = np.linspace(0.0, 4.0, N)


def _trials(rng, earlier_size, extra):
    """Four held-out trials: the model before holds an earlier cause's contribution ``D`` (a rise with its own time
    course) at one size; the data hold it at ``earlier_size[k]`` in trial k, plus ``extra`` (N)."""
    base = 5.0 * np.sin(T)
    shape = 1.0 - np.exp(-T / 0.8)
    meas, before, contrib, noise = {}, {}, {}, {}
    for k, size in enumerate(earlier_size):
        before[k] = base + shape
        contrib[k] = shape
        meas[k] = base + size * shape + extra + ar1(rng, N, 0.03, 0.5)
        noise[k] = noise_level(before[k] - meas[k])
    return list(meas), meas, before, {"earlier": contrib}, noise


#: Each of the four trials of its own kind, as isometric, ramp and random-length trials are.
OWN_KINDS = {0: "isometric", 1: "ramps", 2: "movement", 3: "other"}


def _judged(ids, meas, before, after, noise, contributions, kinds=OWN_KINDS):
    ev = gather(ids, meas, before, after, noise, 2, ["x.k"], (1e4, 10.0),
                {k: WindowSamples(np.ones(N, bool), "defined") for k in ids})
    ev.resize_chi2_gain, ev.beyond_resize_chi2_gain = beyond_resize(ids, meas, before, after, noise, contributions,
                                                                    kinds)
    return apply_rules(ev)


def test_a_candidate_that_takes_up_the_earlier_causes_size_in_each_trial_fails_r8():
    """The data's effect is 0.6-1.6 times the fitted one from trial to trial, each trial of its own kind; a candidate
    whose change is a second term of the same time course, fitted at the average misfit, gains beyond noise but
    nothing beyond the resize."""
    sizes = (0.6, 0.9, 1.3, 1.6)
    ids, meas, before, contrib, noise = _trials(np.random.default_rng(3), sizes, 0.0)
    after = {k: before[k] + 0.3 * contrib["earlier"][k] * (1 if k >= 2 else -1) for k in ids}
    ev = _judged(ids, meas, before, after, noise, contrib)
    assert ev.chi2_gain > ev.bic_penalty and ev.resize_chi2_gain > ev.chi2_gain
    assert ev.beyond_resize_chi2_gain < MIN_BEYOND_RESIZE * ev.chi2_gain and "R8" in ev.failed, ev.text()


def test_one_size_per_kind_does_not_follow_sizes_within_a_kind():
    """The same data and candidate as above with the four trials of one kind: one size for them all takes up their
    average misfit, not its trial-to-trial pattern, and the candidate keeps most of its gain."""
    sizes = (0.6, 0.9, 1.3, 1.6)
    ids, meas, before, contrib, noise = _trials(np.random.default_rng(3), sizes, 0.0)
    after = {k: before[k] + 0.3 * contrib["earlier"][k] * (1 if k >= 2 else -1) for k in ids}
    ev = _judged(ids, meas, before, after, noise, contrib, kinds=dict.fromkeys(ids, "movement"))
    assert ev.beyond_resize_share > 0.8 and "R8" not in ev.failed, ev.text()


def test_trials_of_one_kind_are_resized_together():
    """Two kinds of two trials each: with sizes equal within a kind, one size per kind resizes as well as one per
    trial; the numbers equal those of four kinds."""
    sizes = (0.6, 0.6, 1.5, 1.5)
    ids, meas, before, contrib, noise = _trials(np.random.default_rng(7), sizes, 0.0)
    after = {k: before[k] + 0.3 * contrib["earlier"][k] * (1 if k >= 2 else -1) for k in ids}
    two = beyond_resize(ids, meas, before, after, noise, contrib, {0: "a", 1: "a", 2: "b", 3: "b"})
    four = beyond_resize(ids, meas, before, after, noise, contrib, OWN_KINDS)
    assert two[0] == pytest.approx(four[0], rel=0.01) and abs(two[1]) < 0.05 * two[0]


def test_a_candidate_with_an_effect_of_its_own_passes_r8():
    """The earlier cause's size is right; a second effect with a time course of its own (a dip 2 s in, where the
    earlier one has settled) is in every trial and the candidate has it."""
    decline = -0.4 * np.exp(-(((T - 2.0) / 0.3) ** 2))
    ids, meas, before, contrib, noise = _trials(np.random.default_rng(4), (1.0, 1.0, 1.0, 1.0), decline)
    after = {k: before[k] + decline for k in ids}
    ev = _judged(ids, meas, before, after, noise, contrib)
    # the resize takes up what of the dip looks like the earlier cause (its mean level), not the dip
    assert 0.7 < ev.beyond_resize_share < 1.0 and "R8" not in ev.failed, ev.text()


def test_a_resize_keeps_the_earlier_causes_sign():
    """The data hold the earlier effect reversed: the resize may take it to zero, not past it (three quarters of the
    squared misfit), so a candidate that reverses it keeps the last quarter beyond the resize."""
    ids, meas, before, contrib, noise = _trials(np.random.default_rng(5), (-1.0,) * 4, 0.0)
    after = {k: before[k] - 2.0 * contrib["earlier"][k] for k in ids}
    resize, beyond = beyond_resize(ids, meas, before, after, noise, contrib, OWN_KINDS)
    total = sum(float(((meas[k] - before[k]) ** 2).sum()) * noise[k].chi2_weight for k in ids)
    assert 0.7 * total < resize < 0.8 * total and 0.2 * total < beyond < 0.3 * total


def test_without_a_cause_to_resize_r8_is_not_asked():
    ids, meas, before, contrib, noise = _trials(np.random.default_rng(6), (1.0,) * 4, 0.1)
    after = {k: before[k] + 0.1 for k in ids}
    ev = _judged(ids, meas, before, after, noise, {})
    assert ev.resize_chi2_gain == 0.0 and ev.beyond_resize_chi2_gain == pytest.approx(ev.chi2_gain)
    assert "R8" not in ev.failed
