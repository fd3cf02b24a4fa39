"""Recompute the table of docs/validation/recorded-discharges.md: on every Caillet file of the folder, the human-unit
model and the fitted twitch sum, both calibrated on the first half of the trial, scored on the held-out second half.

Run from the repository root:  python docs/validation/recorded_discharges.py [--data-dir DIR] [--files A.mat,B.mat]
[--transfer] [--pool]
Prints Markdown (about 7 minutes on one core for the eight files; the same fit as ``neuromuscle discharges``).
--transfer adds the table across contraction levels: each trial's fit (of its first half, and of the whole trial)
carried, unchanged, to the other level's trial of the same subject and grid (S1_30_256 and S1_50_256, S1_30_64L and
S1_50_64L, when both were fitted).
--pool adds the completed pool (``neuromuscle.pool.unrecorded_units``: the recorded units and the muscle's
unrecorded ones, P0 from the published spread) to both tables, fitted on the same windows.
Units: NRMSE in % of the recorded range of the window.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from neuromuscle.pool.cross_level import pool_transfer_nrmse, transfer_nrmse
from neuromuscle.pool.discharge_force import DischargeFits, fit_both, read_discharges
from neuromuscle.pool.unrecorded_units import CompletedPool, CompletedPoolFit, complete_pool, fit_completed_pool
from neuromuscle.reports.markdown import table

DATA = Path(__file__).resolve().parents[3] / "shared" / "real_data" / "human_mu_spike_trains_caillet"


#: Pairs of trials of one subject and grid at two contraction levels.
LEVEL_PAIRS = (("S1_30_256", "S1_50_256"), ("S1_30_64L", "S1_50_64L"))


Completed = tuple[CompletedPool, CompletedPoolFit]


def completed(fits: DischargeFits) -> Completed:
    """The trial's completed pool (rate model from the calibration window) and its fit on the same windows."""
    h = fits.human
    pool = complete_pool(fits.trial, fits.thresholds_percent_mvc, fits.bases, until_ms=h.calibration_ms[1])
    return pool, fit_completed_pool(pool, fits.recorded, calibration_ms=h.calibration_ms, heldout_ms=h.heldout_ms)


def one_file(path: Path, pool: bool = False) -> tuple[list[str], DischargeFits, Completed | None]:
    """The table row of one file, its fits, and (``pool``) its completed pool and fit."""
    rec = read_discharges(path)
    trial = rec.trial(pad_ms=1000.0, from_rest=True)
    t0 = time.time()
    fits = fit_both(trial)
    done = completed(fits) if pool else None
    print(f"{path.name}: {time.time() - t0:.0f} s", file=sys.stderr)
    human, reference, thresholds = fits.human, fits.reference, fits.thresholds_percent_mvc
    p, lo_hi = human.params, human.intervals
    wins = "human units" if human.nrmse_heldout_percent < reference.nrmse_heldout_percent else "twitch sum"
    extra = []
    if done is not None:
        c = done[1]
        extra = [f"{c.nrmse_calibration_percent:.1f} / **{c.nrmse_heldout_percent:.1f}**",
                 f"{81.0 / c.params['S0']:.0f} / {c.params['RS']:.2f} / {c.params['delay_ms']:.0f}",
                 str(c.n_unrecorded)]
    return [path.stem, str(len(trial.discharges_ms)), f"{rec.level_percent_mvc:g}",
            f"{thresholds.min():.1f}-{thresholds.max():.1f}",
            f"{human.nrmse_calibration_percent:.1f} / **{human.nrmse_heldout_percent:.1f}**",
            f"{reference.nrmse_calibration_percent:.1f} / **{reference.nrmse_heldout_percent:.1f}**", wins,
            f"{81.0 / p['S0']:.0f} [{81.0 / lo_hi['S0'][1]:.0f}, {81.0 / lo_hi['S0'][0]:.0f}]",
            f"{p['RS']:.2f} [{lo_hi['RS'][0]:.2f}, {lo_hi['RS'][1]:.2f}]",
            f"{p['RP']:.1f} [{lo_hi['RP'][0]:.1f}, {lo_hi['RP'][1]:.1f}]",
            f"{p['W']:.2f} [{lo_hi['W'][0]:.2f}, {lo_hi['W'][1]:.2f}]", f"{p['delay_ms']:.0f}", *extra], fits, done


def transfer_rows(fits: dict[str, DischargeFits], pools: dict[str, Completed] | None = None) -> list[list[str]]:
    """Rows of the table across levels, for every pair of :data:`LEVEL_PAIRS` whose two trials were fitted: each
    trial's first-half fit and its whole-trial fit (same unit forces; the completed pool's same pool) carried to
    the other trial."""
    rows = []
    for a, b in LEVEL_PAIRS:
        if a in fits and b in fits:
            whole = {k: fit_both(fits[k].trial, calibration_fraction=1.0, bases=fits[k].bases) for k in (a, b)}
            whole_pool = {}
            if pools:
                for k in (a, b):
                    end = (0.0, float(fits[k].t_ms[-1]) + 1.0)
                    whole_pool[k] = fit_completed_pool(pools[k][0], fits[k].recorded, calibration_ms=end,
                                                       heldout_ms=end)
            for src, dst in ((a, b), (b, a)):
                for label, source in (("first half", fits[src]), ("whole trial", whole[src])):
                    s = transfer_nrmse(source, fits[dst])
                    carried = [s["human_units"], s["twitch_sum"]]
                    if pools:
                        c_src = pools[src][1] if label == "first half" else whole_pool[src]
                        c = pool_transfer_nrmse(c_src, pools[dst][0], fits[dst].recorded, pools[dst][1])
                        carried.append(c["completed_pool"])
                    best = min(range(len(carried)), key=carried.__getitem__)   # the lowest carried NRMSE in bold
                    row = [f"{src} -> {dst}", label] + [f"**{v:.1f}**" if i == best else f"{v:.1f}"
                                                        for i, v in enumerate(carried)]
                    row += [f"{s['human_units_own']:.1f}", f"{s['twitch_sum_own']:.1f}"]
                    if pools:
                        row.append(f"{c['completed_pool_own']:.1f}")
                    rows.append(row)
    return rows


def main(argv: list[str] | None = None) -> str:
    """Command line (module docstring); returns the Markdown table."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data-dir", default=str(DATA), help="folder of the Caillet .mat files")
    ap.add_argument("--files", default=None, help="comma-separated file names (default: every .mat file)")
    ap.add_argument("--transfer", action="store_true", help="add the table across contraction levels")
    ap.add_argument("--pool", action="store_true", help="add the completed pool (recorded and unrecorded units)")
    a = ap.parse_args(argv)
    folder = Path(a.data_dir)
    files = ([folder / n for n in a.files.split(",")] if a.files else sorted(folder.glob("*.mat")))
    done = {f.stem: one_file(f, a.pool) for f in files}
    rows = [row for row, _, _ in done.values()]
    header = ["file", "units", "level (% MVC)", "thresholds (% MVC)", "human units: NRMSE cal. / held-out (%)",
              "twitch sum: NRMSE cal. / held-out (%)", "lower held-out", "contraction time at 0 % MVC (ms)", "RS",
              "RP", "W", "delay (ms)"]
    if a.pool:
        header += ["completed pool: NRMSE cal. / held-out (%)", "completed pool: contraction time at 0 % MVC (ms) / RS "
                   "/ delay (ms)", "unrecorded units"]
    text = "\n".join(table(header, rows))
    if a.transfer:
        pools = {k: c for k, (_, _, c) in done.items()} if a.pool else None
        head = ["calibrated on -> predicted", "calibration window", "human units: NRMSE (%)", "twitch sum: NRMSE (%)"]
        head += ["completed pool: NRMSE (%)"] if a.pool else []
        head += ["human units, target's own fit", "twitch sum, target's own fit"]
        head += ["completed pool, target's own fit"] if a.pool else []
        text += "\n\n" + "\n".join(table(head, transfer_rows({k: v for k, (_, v, _) in done.items()}, pools)))
    print(text)
    return text


if __name__ == "__main__":
    main()
