"""The automatic split: every protocol on both sides, the held-out trials between calibration ones."""

import copy

import numpy as np
import pytest

from diagnose_datasets import make_data
from neuromuscle.diagnose.split import automatic_split, given_split
from neuromuscle.errors import InputError


def test_automatic_split_puts_each_protocol_on_both_sides():
    data = make_data(0)
    s = automatic_split(data)
    for proto in {t.protocol for t in data.trials.values()}:
        ids = {i for i, t in data.trials.items() if t.protocol == proto}
        assert ids & set(s.calibration) and ids & set(s.heldout)
    g = given_split(data, ["twitch_opt", "long50_opt"])
    assert g.heldout == ("twitch_opt", "long50_opt") and "twitch_opt" not in g.calibration
    with pytest.raises(InputError, match="nosuch"):
        given_split(data, ["nosuch"])


def test_automatic_split_holds_out_between_calibration_trials():
    """Doublets at 5, 10 and 15 ms (same length and stimulus count): the 10 ms one is held out, so the doublet
    extension is judged where it interpolates."""
    data = make_data(0)
    base = data.trials["train20_opt"]
    for isi in (5, 10, 15):
        t = copy.deepcopy(base)
        t.trial_id, t.protocol = f"doublet{isi}_opt", "doublet"
        stim = np.asarray(base.stimulus_times_s, dtype=float)
        t.stimulus_times_s = np.sort(np.append(stim[:-1], stim[0] + isi / 1000.0))
        data.trials[t.trial_id] = t
    s = automatic_split(data)
    assert "doublet10_opt" in s.heldout and {"doublet5_opt", "doublet15_opt"} <= set(s.calibration)
