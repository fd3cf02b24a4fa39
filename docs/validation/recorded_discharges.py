"""Recompute the table of docs/validation/recorded-discharges.md: on every Caillet file of the folder, the human-unit
model and the fitted twitch sum, both calibrated on the first half of the trial, scored on the held-out second half.

Run from the repository root:  python docs/validation/recorded_discharges.py [--data-dir DIR] [--files A.mat,B.mat]
[--transfer]
Prints Markdown (about 7 minutes on one core for the eight files; the same fit as ``neuromuscle discharges``).
--transfer adds the table across contraction levels: each trial's fit (of its first half, and of the whole trial)
carried, unchanged, to the other level's trial of the same subject and grid (S1_30_256 and S1_50_256, S1_30_64L and
S1_50_64L, when both were fitted).
Units: NRMSE in % of the recorded range of the window.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from neuromuscle.pool.cross_level import transfer_nrmse
from neuromuscle.pool.discharge_force import DischargeFits, fit_both, read_discharges
from neuromuscle.reports.markdown import table

DATA = Path(__file__).resolve().parents[3] / "shared" / "real_data" / "human_mu_spike_trains_caillet"


#: Pairs of trials of one subject and grid at two contraction levels.
LEVEL_PAIRS = (("S1_30_256", "S1_50_256"), ("S1_30_64L", "S1_50_64L"))


def one_file(path: Path) -> tuple[list[str], DischargeFits]:
    """The table row of one file, and its fits."""
    rec = read_discharges(path)
    trial = rec.trial(pad_ms=1000.0)
    t0 = time.time()
    fits = fit_both(trial)
    print(f"{path.name}: {time.time() - t0:.0f} s", file=sys.stderr)
    human, reference, thresholds = fits.human, fits.reference, fits.thresholds_percent_mvc
    p, lo_hi = human.params, human.intervals
    wins = "human units" if human.nrmse_heldout_percent < reference.nrmse_heldout_percent else "twitch sum"
    return [path.stem, str(len(trial.discharges_ms)), f"{rec.level_percent_mvc:g}",
            f"{thresholds.min():.1f}-{thresholds.max():.1f}",
            f"{human.nrmse_calibration_percent:.1f} / **{human.nrmse_heldout_percent:.1f}**",
            f"{reference.nrmse_calibration_percent:.1f} / **{reference.nrmse_heldout_percent:.1f}**", wins,
            f"{81.0 / p['S0']:.0f} [{81.0 / lo_hi['S0'][1]:.0f}, {81.0 / lo_hi['S0'][0]:.0f}]",
            f"{p['RS']:.2f} [{lo_hi['RS'][0]:.2f}, {lo_hi['RS'][1]:.2f}]",
            f"{p['RP']:.1f} [{lo_hi['RP'][0]:.1f}, {lo_hi['RP'][1]:.1f}]",
            f"{p['W']:.2f} [{lo_hi['W'][0]:.2f}, {lo_hi['W'][1]:.2f}]", f"{p['delay_ms']:.0f}"], fits


def transfer_rows(fits: dict[str, DischargeFits]) -> list[list[str]]:
    """Rows of the table across levels, for every pair of :data:`LEVEL_PAIRS` whose two trials were fitted: each
    trial's first-half fit and its whole-trial fit (same unit forces) carried to the other trial."""
    rows = []
    for a, b in LEVEL_PAIRS:
        if a in fits and b in fits:
            whole = {k: fit_both(fits[k].trial, calibration_fraction=1.0, bases=fits[k].bases) for k in (a, b)}
            for src, dst in ((a, b), (b, a)):
                for label, source in (("first half", fits[src]), ("whole trial", whole[src])):
                    s = transfer_nrmse(source, fits[dst])
                    rows.append([f"{src} -> {dst}", label, f"{s['human_units']:.1f}", f"{s['twitch_sum']:.1f}",
                                 f"{s['human_units_own']:.1f}", f"{s['twitch_sum_own']:.1f}"])
    return rows


def main(argv: list[str] | None = None) -> str:
    """Command line (module docstring); returns the Markdown table."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data-dir", default=str(DATA), help="folder of the Caillet .mat files")
    ap.add_argument("--files", default=None, help="comma-separated file names (default: every .mat file)")
    ap.add_argument("--transfer", action="store_true", help="add the table across contraction levels")
    a = ap.parse_args(argv)
    folder = Path(a.data_dir)
    files = ([folder / n for n in a.files.split(",")] if a.files else sorted(folder.glob("*.mat")))
    done = {f.stem: one_file(f) for f in files}
    rows = [row for row, _ in done.values()]
    header = ["file", "units", "level (% MVC)", "thresholds (% MVC)", "human units: NRMSE cal. / held-out (%)",
              "twitch sum: NRMSE cal. / held-out (%)", "lower held-out", "contraction time at 0 % MVC (ms)", "RS",
              "RP", "W", "delay (ms)"]
    text = "\n".join(table(header, rows))
    if a.transfer:
        text += "\n\n" + "\n".join(table(
            ["calibrated on -> predicted", "calibration window", "human units: NRMSE (%)", "twitch sum: NRMSE (%)",
             "human units, target's own fit", "twitch sum, target's own fit"],
            transfer_rows({k: v for k, (_, v) in done.items()})))
    print(text)
    return text


if __name__ == "__main__":
    main()
