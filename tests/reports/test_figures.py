"""Every figure the fit report and the twitch-to-tetanus workflow write: each panel's axes labelled with a unit in
parentheses (an x axis shared with the panel below may carry its label there), no title printing a dict/repr."""

import re
import sys
from pathlib import Path

import pytest
from matplotlib.figure import Figure

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "calibration"))

from calibration_synthetic import synthetic_data  # noqa: E402

from neuromuscle.hatze.report import FIGURES  # noqa: E402
from neuromuscle.hatze.workflow import run_twitch_to_tetanus  # noqa: E402
from neuromuscle.measured import write_measured  # noqa: E402
from neuromuscle.reports.figures import label_axes, new_figure, readable_title, save_figure  # noqa: E402
from neuromuscle.calibration.report import run_fit  # noqa: E402

UNIT = re.compile(r"\(.+\)")


def problems(fig: Figure) -> list[str]:
    """What a reader would miss on ``fig``: labels without units, titles with braces."""
    out = []
    for i, ax in enumerate(fig.axes):
        if not UNIT.search(ax.get_ylabel()):
            out.append(f"panel {i}: y label {ax.get_ylabel()!r}")
        xlabels = [a.get_xlabel() for a in ax.get_shared_x_axes().get_siblings(ax)]
        if not any(UNIT.search(x) for x in xlabels):
            out.append(f"panel {i}: x label {ax.get_xlabel()!r}")
        for title in (ax.get_title(loc) for loc in ("left", "center", "right")):
            if "{" in title or "}" in title:
                out.append(f"panel {i}: title {title!r}")
    return out


@pytest.fixture
def written(monkeypatch):
    """Every figure saved while the test runs, with its file name."""
    saved: list[tuple[str, Figure]] = []
    original = Figure.savefig

    def record(fig, fname, *args, **kwargs):
        saved.append((Path(fname).name.removesuffix(".part"), fig))
        return original(fig, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", record)
    return saved


def test_fit_report_figures_are_labelled(written, tmp_path, ct09):
    data = synthetic_data(ct09.with_values(C3=70.0), full=True)
    data.trials = {k: v for k, v in data.trials.items() if k in ("twitch_opt", "train20")}
    data.extra_datasets.clear()
    h5 = write_measured(tmp_path / "small.h5", data)
    run_fit(h5, tmp_path / "fit", free=["C3"], dt_ms=0.1, max_iterations=2)
    assert sorted(name for name, _ in written) == ["train20.png", "twitch_opt.png"]
    assert {name: problems(fig) for name, fig in written} == {name: [] for name, _ in written}
    assert not list((tmp_path / "fit").rglob("*.part"))


def test_twitch_to_tetanus_figures_are_labelled(written, tmp_path):
    run_twitch_to_tetanus(tmp_path / "t2t", max_evaluations=3)
    assert [name for name, _ in written] == list(FIGURES)
    assert {name: problems(fig) for name, fig in written} == {name: [] for name in FIGURES}
    rise = dict(written)["rise_times.png"]
    assert all(ax.get_ylabel() for ax in rise.axes)                 # both panels, not only the left one


def test_label_axes_demands_units():
    fig, (ax,) = new_figure()
    with pytest.raises(ValueError, match="no unit"):
        label_axes(ax, x="time", y="force (N)")
    with pytest.raises(ValueError, match="no unit"):
        label_axes(ax, x="time (s)", y="force")
    label_axes(ax, x="time (ms)", y="force (N)")
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("time (ms)", "force (N)")


def test_readable_title_never_prints_a_repr():
    title = readable_title("trial 3 (isometric)", {"C1": 1.234567, "C3": 70})
    assert title == "trial 3 (isometric); C1 = 1.235, C3 = 70"
    assert readable_title("NRMSE (%)", 0.123456) == "NRMSE (%); 0.1235"
    assert readable_title("trial {'a': 1}") == "trial ('a': 1)"
    for bad in (object(), [1, 2], None):
        with pytest.raises(ValueError, match="not readable"):
            readable_title(bad)


def test_save_figure_writes_png_atomically(tmp_path):
    fig, axes = new_figure(2, columns=True)
    for ax in axes:
        label_axes(ax, x="time (s)", y="force (N)")
    path = tmp_path / "f.png"
    save_figure(fig, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and [p.name for p in tmp_path.iterdir()] == ["f.png"]
