"""Force from recorded discharges: the decomposed HD-EMG discharges of human tibialis anterior units (Caillet et
al. 2023, PLoS Comput Biol 19:e1011606; data in ../shared/real_data/human_mu_spike_trains_caillet, read by path)
drive one muscle unit each, fitted to human motor units by recruitment threshold, beside a fitted twitch sum; both
are calibrated on the first half of the contraction and predict the second half, which they never see.

This is what ``neuromuscle discharges FILE --out DIR`` does (neuromuscle.pool.discharge_force), on a file of the
Caillet folder by name.

Run: python networks/recorded_discharges.py --out DIR [--file S1_30_256.mat] [--full] [--overwrite]
Default: S1_30_36L (17 units, 33 s), dt 0.05 ms.  --full: S1_30_256 (84 units), dt 0.025 ms.
Writes DIR/discharges.h5 (schema neuromuscle.discharge_force/1, provenance), .png and .json; prints the summary
as JSON.  Units: ms, % MVC.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from neuromuscle.pool.discharge_force import run_discharges

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "real_data" / "human_mu_spike_trains_caillet"


def main(argv: list[str] | None = None) -> dict:
    """Command line (module docstring); returns the summary."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--file", help="a Caillet .mat file, a path or a name in --data-dir (default S1_30_36L, "
                                   "--full S1_30_256)")
    ap.add_argument("--data-dir", default=str(DATA), help="folder of the Caillet files")
    ap.add_argument("--full", action="store_true", help="S1_30_256 (84 units) at dt 0.025 ms")
    ap.add_argument("--calibration-fraction", type=float, default=0.5, help="share of the trial fitted on")
    ap.add_argument("--overwrite", action="store_true")
    a = ap.parse_args(argv)
    path = Path(a.file) if a.file and Path(a.file).is_file() else Path(a.data_dir) / (
        a.file or ("S1_30_256.mat" if a.full else "S1_30_36L.mat"))
    summary = run_discharges(path, a.out, calibration_fraction=a.calibration_fraction,
                             dt_ms=0.025 if a.full else 0.05, overwrite=a.overwrite)
    print(json.dumps(summary, indent=1, default=float))
    return summary


if __name__ == "__main__":
    main()
