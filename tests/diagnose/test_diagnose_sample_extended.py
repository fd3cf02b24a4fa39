"""The CI sample, extended design: a null of world A, a blind diagnosis that names what the file holds
(sample_cases.py); a world-B file with one cause runs with the slow tests.  World B's file of the sample, with two
hidden causes: test_diagnose_sample_two_effect.py."""

import pytest
from sample_cases import diagnose_case

pytestmark = pytest.mark.heavy(cost_s=40)


@pytest.mark.slow
def test_world_b_names_the_hidden_doublet():
    d = diagnose_case("B doublet")
    assert d.named == ["doublet_potentiation"], d.named


def test_world_a_with_no_hidden_effect_names_eq18_alone():
    """The paper's full model: its eq 18 is what the baseline lacks, and nothing else."""
    d = diagnose_case("A null")
    assert d.named == ["length_dependent_activation"], d.named
    ev = d.steps[0].candidates["length_dependent_activation"].evidence
    assert ev.excess_removed > 0.5
