"""Recordings by name: "slot.variable" resolved through the unit's components, unknown names refused."""

import pytest

from neuromuscle import InputError, simulate
from neuromuscle.protocols import twitch


def test_named_recordings_with_units(ct09):
    r = simulate(ct09, twitch(50.0), -8.0, 200.0, record=("force.F", "ca.CaSPT", "act.tauA", "force.vce"))
    assert list(r.traces) == ["force.F", "ca.CaSPT", "act.tauA", "force.vce"]
    assert r.units == {"force.F": "N", "ca.CaSPT": "M", "act.tauA": "ms", "force.vce": "mm/s"}
    assert r["ca.CaSPT"].max() > 0 and r.force_N is r["force.F"]


@pytest.mark.parametrize("names, match", [(("force.X",), "cannot record"), (("nowhere.F",), "cannot record"),
                                          (("F",), "cannot record"), (("force.F", "force.F"), "repeat")])
def test_unknown_or_malformed_names_are_refused(ct09, names, match):
    with pytest.raises(InputError, match=match):
        simulate(ct09, twitch(50.0), -8.0, 100.0, record=names)
