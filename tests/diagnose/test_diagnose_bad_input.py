"""Bad input: a clear message naming the problem, exit code 2, nothing written."""

import numpy as np

from neuromuscle.cli import main


def _run(path, out, capsys, *extra):
    code = main(["diagnose", str(path), "--out", str(out), "--quiet", *extra])
    return code, capsys.readouterr().err


def test_too_few_trials(small_file, tmp_path, capsys):
    def keep_four(d):
        for k in list(d.trials)[4:]:
            del d.trials[k]
    code, err = _run(small_file(keep_four), tmp_path / "out", capsys)
    assert code == 2 and "too few trials" in err and not (tmp_path / "out").exists()


def test_trial_without_stimulus(small_file, tmp_path, capsys):
    def silence(d):
        d.trials["train20_opt"].stimulus_times_s = np.zeros(0)
    code, err = _run(small_file(silence), tmp_path / "out", capsys)
    assert code == 2 and "train20_opt" in err and "no stimulus" in err and not (tmp_path / "out").exists()


def test_force_in_wrong_unit(small_file, tmp_path, capsys):
    def moment(d):
        d.trials["twitch_opt"].force_unit = "N*m"
    code, err = _run(small_file(moment), tmp_path / "out", capsys)
    assert code == 2 and "twitch_opt" in err and "N*m" in err and not (tmp_path / "out").exists()


def test_force_in_millinewton_labelled_newton(small_file, tmp_path, capsys):
    def milli(d):
        for t in d.trials.values():
            t.force = t.force * 1000.0
    code, err = _run(small_file(milli), tmp_path / "out", capsys)
    assert code == 2 and "not in N" in err and not (tmp_path / "out").exists()


def test_split_naming_unknown_trials(small_file, tmp_path, capsys):
    code, err = _run(small_file(), tmp_path / "out", capsys, "--split", "heldout=twitch_opt,nosuch")
    assert code == 2 and "nosuch" in err and not (tmp_path / "out").exists()
