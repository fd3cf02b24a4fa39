"""The CI sample, extended design: a null of world A and a world-B file with a hidden staircase, blind diagnoses that
name what the file holds and nothing else (sample_cases.py); a world-B file with a hidden doublet runs with the slow
tests."""

import pytest
from sample_cases import diagnose_case

pytestmark = pytest.mark.heavy(cost_s=90)


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


def test_world_b_names_the_hidden_staircase_alone():
    d = diagnose_case("B staircase")
    assert d.named == ["staircase"], d.named
    assert d.baseline.model.converged
