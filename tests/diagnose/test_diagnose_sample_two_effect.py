"""The CI sample's two-effect file (world B-reduced: staircase and relaxation rate on the reduced design): both
hidden causes named, the second judged against the model with the first (sample_cases.py); world B's extended
two-effect file (staircase and doublet) runs with the slow tests.  A file of its own, so that it runs beside the
sample's other diagnoses under pytest-xdist."""

import pytest

from sample_cases import diagnose_case

pytestmark = pytest.mark.heavy(cost_s=70)


def _both_named(d, causes):
    assert sorted(d.named) == sorted(causes), d.named
    first = d.steps[0]
    assert first.named in causes
    second = d.steps[1]
    assert second.before.extensions == (first.named,)  # the second is judged against the model with the first


def test_two_hidden_causes_are_both_named():
    _both_named(diagnose_case("B-reduced staircase and relaxation"), ("relaxation_rate", "staircase"))


@pytest.mark.slow
def test_two_hidden_causes_of_the_extended_design_are_both_named():
    _both_named(diagnose_case("B staircase and doublet"), ("doublet_potentiation", "staircase"))
