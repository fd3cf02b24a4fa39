"""The CI sample's two-effect file (world B, extended design): both hidden causes named, the second judged against
the model with the first (sample_cases.py).  A file of its own, so that the sample's longest diagnosis runs beside
the others under pytest-xdist."""

import pytest

from sample_cases import diagnose_case

pytestmark = pytest.mark.heavy(cost_s=170)


def test_two_hidden_causes_are_both_named():
    d = diagnose_case("B staircase and doublet")
    assert sorted(d.named) == ["doublet_potentiation", "staircase"], d.named
    first = d.steps[0]
    assert first.named in ("doublet_potentiation", "staircase")
    second = d.steps[1]
    assert second.before.extensions == (first.named,)  # the second is judged against the model with the first
