"""The CI sample, extended design (worlds A and B): a null of world A and a world-B file with two hidden causes,
blind diagnoses that name what the file holds (sample_cases.py); a world-B file with one cause runs with the slow
tests."""

import pytest
from sample_cases import diagnose_case


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


def test_two_hidden_causes_are_both_named():
    d = diagnose_case("B staircase and doublet")
    assert sorted(d.named) == ["doublet_potentiation", "staircase"], d.named
    first = d.steps[0]
    assert first.named in ("doublet_potentiation", "staircase")
    second = d.steps[1]
    assert second.before.extensions == (first.named,)  # the second is judged against the model with the first
