"""Self-consistent calculation (van Zandwijk et al. 1998, eqs 3-4) on synthesised isokinetic releases."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.hatze.contraction import simulate_release
from neuromuscle.model.hatze_parameters import load_subject
from neuromuscle.hatze.scc import Release, self_consistent_calculation

VELOCITIES = (3.0, 5.0, 10.0, 15.0)                 # rad/s, as in the paper's Fig 3


def _releases(subject, velocities=VELOCITIES, **kw):
    return [simulate_release(subject, v, **kw) for v in velocities]


@pytest.mark.parametrize("name", ["1", "3"])
def test_scc_recovers_ce_and_see_relations(name):
    """With a flat moment-angle relation the releases satisfy the SCC's assumptions exactly; what remains is the
    numerical differentiation (eq 3) and integration (eq 4) of 2 kHz samples."""
    truth = load_subject(name).with_values(w=1e6)
    res = self_consistent_calculation(_releases(truth))
    assert res.k_see == pytest.approx(truth.k_see, rel=3e-3)
    assert res.a_rel == pytest.approx(truth.a_rel, rel=3e-3)
    assert res.b_rad_s == pytest.approx(truth.b, rel=3e-3)
    assert res.b_rel(truth.phi_ce_opt) == pytest.approx(truth.b_rel, rel=3e-3)
    assert res.fastest_release == 3 and res.m_init_nm == pytest.approx(truth.m_max, rel=1e-4)


def test_scc_with_the_ce_moment_angle_parabola():
    """Table 1 subject 3 as it is (w = 0.56): the CE leaves its optimum during the releases; restricting the CE
    points to 0.1 rad of CE excursion keeps the bias to about 1 %."""
    truth = load_subject("3")
    res = self_consistent_calculation(_releases(truth))
    assert res.k_see == pytest.approx(truth.k_see, rel=0.02)
    assert res.a_rel == pytest.approx(truth.a_rel, rel=0.02)
    assert res.b_rad_s == pytest.approx(truth.b, rel=0.03)


def test_scc_refuses_data_without_a_fast_enough_release():
    truth = load_subject("3").with_values(w=1e6)    # v_max = b/a_rel = 8.9 rad/s
    slow = _releases(truth, (3.0, 5.0, 7.0), displacement_rad=0.5)
    with pytest.raises(InputError, match=r"fastest release \(releases\[2\].*reach zero"):
        self_consistent_calculation(slow)


def test_scc_accepts_triples_and_release_objects():
    truth = load_subject("3").with_values(w=1e6)
    rels = _releases(truth)
    mixed = [tuple(rels[0]), Release(*rels[1]), list(rels[2]), rels[3]]
    assert self_consistent_calculation(mixed).k_see == pytest.approx(self_consistent_calculation(rels).k_see)


@pytest.mark.parametrize("mutate, culprit", [
    (lambda r: r[:1], "at least 2 releases"),
    (lambda r: [r[0], (r[1][0], r[1][1], np.where(r[1][0] > 0.1, np.nan, r[1][2])), r[2]],
     r"releases\[1\]\.moment_nm contains non-finite"),
    (lambda r: [r[0], (r[1][0], r[1][1][:-1], r[1][2]), r[2]], r"releases\[1\]: t_s, mtc_angle_rad"),
    (lambda r: [r[0], (r[1][0][::-1], r[1][1], r[1][2]), r[2]], r"releases\[1\]\.t_s must increase"),
    (lambda r: [r[0], (r[1][0], np.zeros_like(r[1][1]), r[1][2]), r[2]], r"releases\[1\]: the MTC angle never"),
    (lambda r: [r[0], "data", r[2]], r"releases\[1\] must be"),
])
def test_scc_bad_inputs(mutate, culprit):
    truth = load_subject("3").with_values(w=1e6)
    rels = [tuple(r) for r in _releases(truth, (3.0, 10.0, 15.0))]
    with pytest.raises(InputError, match=culprit):
        self_consistent_calculation(mutate(rels))
