"""The CI sample, reduced in situ design: a blind diagnosis of world A-reduced that names what the file holds
(sample_cases.py; B-reduced's file of the sample, with two hidden causes: test_diagnose_sample_two_effect.py).  A
file of world A carries the paper's eq 18: length_dependent_activation must be named beside its hidden cause.  With
the slow tests: B-reduced's relaxation alone and a null of world B-reduced (the sample's null is world A's)."""

import pytest
from sample_cases import diagnose_case

pytestmark = pytest.mark.heavy(cost_s=90)


def test_world_a_reduced_names_eq18_and_the_hidden_staircase():
    d = diagnose_case("A-reduced staircase")
    assert sorted(d.named) == ["length_dependent_activation", "staircase"], d.named
    for s in d.steps:
        for n in s.named_causes:
            assert s.evidence_of(n).passed


@pytest.mark.slow
def test_world_b_reduced_names_the_hidden_relaxation_alone():
    d = diagnose_case("B-reduced relaxation")
    assert d.named == ["relaxation_rate"], d.named
    assert d.baseline.model.converged


@pytest.mark.slow
def test_a_null_names_nothing():
    d = diagnose_case("B-reduced null")
    assert d.named == [] and d.verdict == "none", [(s.index, {n: c.evidence.failed for n, c in s.candidates.items()
                                                              if c.evidence}) for s in d.steps]
