"""Force from a file of recorded discharges: read (Caillet .mat or an openhdemg file), calibrate two models on the
first part of the trial, predict the rest, and write a figure, an HDF5 file with provenance and a JSON summary.

    summary = run_discharges("S1_30_256.mat", "out/s1_30")     # what ``neuromuscle discharges`` does

The two models, fitted on the same calibration window (the first ``calibration_fraction`` of the trial):

- human units (:mod:`.human_units`): one Kim muscle unit per recorded unit, twitch speed and P0 as functions of the
  recruitment threshold (% MVC), within priors from published human motor-unit properties;
- the twitch-sum reference (:mod:`.twitch_sum`): Fuglevand-style twitches, peak force and contraction time as
  functions of the recruitment rank, with the sigmoid rate gain.

Both are scored by the NRMSE (% of the window's recorded range) on the held-out rest of the trial.  A bad input file
is refused (InputError naming the file and the field) before anything is written.  Units: ms, % MVC.
"""

from __future__ import annotations

import hashlib
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..parameters import load_parameters
from .discharges import REST_MARGIN_MS, REST_PERCENT_MVC, DischargeTrial, RecordedDischarges, load_caillet
from .human_units import SPEED_GRID, HumanUnitFit, SpeedBases, fit_human_units, speed_bases
from .openhdemg_files import KINDS, load_openhdemg
from .twitch_sum import TwitchSumFit, fit_twitch_sum

#: Input formats: Caillet .mat, or a file openhdemg opens (its JSON, an OTBiolab+ export, a DEMUSE result).
FORMATS = ("auto", "caillet", *(f"openhdemg-{k}" for k in KINDS))
#: Files written into the output folder.
FILES = ("discharges.h5", "discharges.png", "discharges.json")
#: HDF5 schema of the written file.
SCHEMA = "neuromuscle.discharge_force/1"
#: The muscle parameter set every unit starts from, and its length (mm).
BASE_SET, LENGTH_MM = "CT09", -8.0


def resolved_format(path: Path, fmt: str) -> str:
    """``fmt`` (one of :data:`FORMATS`) with auto resolved from the suffix: openhdemg JSON for .json, Caillet for
    .mat; anything else raises InputError naming the file."""
    if fmt not in FORMATS:
        raise InputError(f"{path}: format must be one of {', '.join(FORMATS)}, got {fmt!r}")
    if fmt != "auto":
        return fmt
    found = {".json": "openhdemg-json", ".mat": "caillet"}.get(path.suffix.lower())
    if found is None:
        raise InputError(f"{path}: cannot tell the format from the suffix {path.suffix!r}; give one of "
                         f"{', '.join(FORMATS[1:])}")
    return found


def read_discharges(path: str | Path, fmt: str = "auto", level_percent_mvc: float | None = None
                    ) -> RecordedDischarges:
    """Read ``path`` in ``fmt`` (one of :data:`FORMATS`; auto: openhdemg JSON for .json, Caillet for .mat)."""
    p = Path(path)
    fmt = resolved_format(p, fmt)
    if fmt == "caillet":
        return load_caillet(p, level_percent_mvc)
    return load_openhdemg(p, fmt.split("-", 1)[1], level_percent_mvc)


def file_sha256(path: str | Path) -> str:
    """SHA-256 (hex) of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def calibration_thresholds(trial: DischargeTrial, split_ms: float) -> np.ndarray:
    """Each unit's recruitment threshold (% MVC, recruitment order) read from the calibration window only: the
    recorded force at its first discharge, or for a unit first discharging after ``split_ms`` (ms) the highest
    force of the window (it was recruited above everything the window saw)."""
    first = np.array([d[0] for d in trial.discharges_ms])
    cal = trial.force_t_ms < split_ms
    top = float(trial.force_percent_mvc[cal].max()) if cal.any() else 0.0
    return np.where(first < split_ms, trial.force_at(first), top)


@dataclass(frozen=True)
class DischargeFits:
    """Both models fitted on one trial: the trial, its unit forces at every grid speed, the thresholds (% MVC,
    from the calibration window), the recorded force (% MVC) at ``bases.t_ms`` and the two fits."""

    trial: DischargeTrial
    bases: SpeedBases
    thresholds_percent_mvc: np.ndarray
    recorded: np.ndarray
    human: HumanUnitFit
    reference: TwitchSumFit

    @property
    def t_ms(self) -> np.ndarray:
        """Sample times (ms from the trial's start)."""
        return self.bases.t_ms


def fit_both(trial: DischargeTrial, *, calibration_fraction: float = 0.5, dt_ms: float = 0.05,
             speeds: tuple[float, ...] = SPEED_GRID, bases: SpeedBases | None = None) -> DischargeFits:
    """Both models fitted on the first ``calibration_fraction`` of ``trial`` (thresholds from that window:
    :func:`calibration_thresholds`).  A fraction of 1 fits the whole trial (to carry it to another one): there is
    no held-out time, and the held-out scores repeat the calibration's.  ``bases``: the trial's unit forces from an
    earlier fit, reused instead of simulated again."""
    if not 0.05 <= calibration_fraction <= 1.0:
        raise InputError(f"calibration fraction must lie in [0.05, 1], got {calibration_fraction}")
    if bases is None:
        bases = speed_bases(trial.discharges_ms, trial.duration_ms, load_parameters(BASE_SET), speeds=speeds,
                            dt_ms=dt_ms, length_mm=LENGTH_MM)
    t = bases.t_ms
    y = trial.force_at(t)
    end = float(t[-1]) + 1.0
    split = calibration_fraction * trial.duration_ms if calibration_fraction < 1.0 else end
    windows = {"calibration_ms": (0.0, split), "heldout_ms": (split, end) if split < end else (0.0, end)}
    thresholds = calibration_thresholds(trial, split)
    human = fit_human_units(bases, thresholds, y, **windows)
    reference = fit_twitch_sum(trial.discharges_ms, t, recruitment_rank(len(trial.discharges_ms)), y, **windows)
    return DischargeFits(trial, bases, thresholds, y, human, reference)


def recruitment_rank(n_units: int) -> np.ndarray:
    """Positions 0..1 of ``n_units`` units in recruitment order (the twitch sum's x)."""
    return np.arange(n_units) / max(n_units - 1, 1)


def _figure(path: Path, name: str, trial: DischargeTrial, t_ms: np.ndarray, y: np.ndarray, human: HumanUnitFit,
            reference: TwitchSumFit) -> None:
    from ..reports.figures import label_axes, legend, new_figure, residual_panel, save_figure, set_title

    t = t_ms / 1000.0
    fig, axes = new_figure(3, height_ratios=[1.4, 2.2, 1.0], sharex=True)
    for i, d in enumerate(trial.discharges_ms):
        axes[0].plot(d / 1000.0, np.full(d.size, i), "|", ms=1.5, color="k")
    label_axes(axes[0], x=None, y="unit (threshold order)")
    set_title(axes[0], f"{name}: {len(trial.discharges_ms)} recorded units")
    axes[1].plot(t, y, color="0.5", lw=1.0, label="recorded")
    axes[1].plot(t, human.predicted, color="C3", lw=1.0,
                 label=f"human units: held-out NRMSE {human.nrmse_heldout_percent:.1f} %")
    axes[1].plot(t, reference.predicted, color="C0", lw=0.8, ls="--",
                 label=f"twitch sum: held-out NRMSE {reference.nrmse_heldout_percent:.1f} %")
    axes[1].axvspan(0.0, human.calibration_ms[1] / 1000.0, color="C0", alpha=0.08, label="calibration window")
    legend(axes[1], small=True)
    label_axes(axes[1], x=None, y="force (% MVC)")
    residual_panel(axes[2], t, human.predicted - y, x="time (s)", y="human units - recorded (% MVC)")
    save_figure(fig, path)


def _write_h5(path: Path, t_ms: np.ndarray, y: np.ndarray, trial: DischargeTrial, thresholds: np.ndarray,
              human: HumanUnitFit, reference: TwitchSumFit, provenance_fields: dict[str, Any]) -> None:
    import h5py

    from ..reports.outdir import atomic_path
    from ..sim.provenance import provenance

    with atomic_path(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["schema"] = SCHEMA
        f.attrs["provenance"] = json.dumps(provenance(**provenance_fields), default=str)
        f.attrs["human_units_fit"] = json.dumps(human.summary(), default=float)
        f.attrs["twitch_sum_fit"] = json.dumps(reference.summary(), default=float)
        f.attrs["force_unit"] = "% MVC"
        f.create_dataset("t_ms", data=t_ms)
        f.create_dataset("recorded_force", data=y)
        f.create_dataset("predicted_force_human_units", data=human.predicted)
        f.create_dataset("predicted_force_twitch_sum", data=reference.predicted)
        f.create_dataset("threshold_percent_mvc", data=thresholds)
        f.create_dataset("unit_speed", data=human.speeds)
        f.create_dataset("unit_p0_relative", data=human.p0)
        f.create_dataset("file_unit_index", data=trial.units)
        g = f.create_group("discharges_ms")
        for i, d in enumerate(trial.discharges_ms):
            g.create_dataset(f"unit_{i}", data=np.asarray(d, float))


def run_discharges(path: str | Path, out: str | Path, *, fmt: str = "auto", level_percent_mvc: float | None = None,
                   calibration_fraction: float = 0.5, dt_ms: float = 0.05, overwrite: bool = False
                   ) -> dict[str, Any]:
    """Read ``path``, fit both models on the whole contraction (:meth:`RecordedDischarges.trial` from rest), write
    :data:`FILES` into ``out``; returns the summary (also in discharges.json).  Nothing is written when the file or
    ``out`` is refused."""
    from ..reports.outdir import check_out_dir, prepare_out_dir, write_text

    if not 0.05 <= calibration_fraction <= 0.95:
        raise InputError(f"calibration fraction must lie in [0.05, 0.95] (the rest is held out), got "
                         f"{calibration_fraction}")
    check_out_dir(out, overwrite, FILES)
    rec = read_discharges(path, fmt, level_percent_mvc)
    trial = rec.trial(pad_ms=1000.0, from_rest=True)
    t0 = time.time()
    fits = fit_both(trial, calibration_fraction=calibration_fraction, dt_ms=dt_ms)
    t, y, thresholds, human, reference = fits.t_ms, fits.recorded, fits.thresholds_percent_mvc, fits.human, \
        fits.reference
    outdir = prepare_out_dir(out, overwrite, FILES)
    src = Path(path)
    summary = {"file": src.name, "units": len(trial.discharges_ms), "level_percent_mvc": rec.level_percent_mvc,
               "duration_ms": trial.duration_ms, "calibration_fraction": calibration_fraction,
               "human_units": human.summary(), "twitch_sum": reference.summary(),
               "wall_s": round(time.time() - t0, 1)}
    fmt = resolved_format(src, fmt)
    fields = {"input_file": str(src.resolve()), "input_sha256": file_sha256(src), "format": fmt,
              "trial_start_ms": trial.start_ms, "trial_duration_ms": trial.duration_ms,
              "window": f"from rest to rest ({REST_PERCENT_MVC:g} % MVC, {REST_MARGIN_MS:g} ms margins)",
              "dt_ms": dt_ms, "speed_grid": list(SPEED_GRID),
              "muscle_set": BASE_SET, "parameters": dict(load_parameters(BASE_SET).values), "length_mm": LENGTH_MM,
              "calibration_fraction": calibration_fraction, "level_percent_mvc": rec.level_percent_mvc}
    if fmt.startswith("openhdemg"):
        from importlib.metadata import version

        fields["openhdemg_version"] = version("openhdemg")
    _write_h5(outdir / FILES[0], t, y, trial, thresholds, human, reference, fields)
    _figure(outdir / FILES[1], src.stem, trial, t, y, human, reference)
    write_text(outdir / FILES[2], json.dumps({**summary, "provenance": fields}, indent=1, default=float) + "\n")
    return summary
