"""Convert the Herzog & Leonard (2002) cat soleus stretch recordings to the measured-data layout.

Run:  python networks/herzog_leonard_to_measured.py --out hl2002.h5 [--real-data ../shared/real_data]
          [--figures Figure7A,Figure7B,Figure7C] [--shift-mm -8] [--rate-hz 30] [--tail-s 0.5] [--overwrite]
then: neuromuscle data check hl2002.h5
      neuromuscle diagnose hl2002.h5 --out hl2002_diagnosis --workers 2 --split heldout=Figure7B_F51,...

What it does, and why (the same text is written into the file's /preprocessing attributes; the code is
neuromuscle.literature.herzog_leonard_measured):
* trials: the Figure 7 trials (one preparation), isometric at 0 and +9 mm and active stretches 0/3/6 -> 9 mm at
  3, 9 and 27 mm/s; the unstimulated stretches only serve the passive fit (kept under /preprocessing/passive);
* stimulus times: a 30 Hz train (the paper's tetanic rate), first stimulus 107.5 ms before the trial's 50 % force
  rise, last one 119.1 ms before the 50 % force fall of the figure's isometric trials (CT09's own 30 Hz delays);
* length: paper mm - 8 mm (the paper's 0 mm at the model's optimum g1 = -8 mm; the paper places these stretches
  on the descending limb); isometric lengths as their median, ramps as the fitted hold-ramp-hold trajectory;
* passive force: the model has no parallel elastic element; F_p(x) = A exp(x / lambda) + C fitted to every
  unstimulated sample is subtracted from every trial;
* window: each trial ends 0.5 s after its last stimulus (the passive force enhancement after deactivation is
  outside any model without a passive element: reported per trial, attr passive_force_enhancement_N).
Units: s, mm, N.  Prints one line per trial (peak force, stimuli) and refuses to overwrite --out unless
--overwrite.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from neuromuscle.errors import InputError
from neuromuscle.literature.herzog_leonard_measured import (DEFAULT_FIGURES, LENGTH_SHIFT_MM, STIMULUS_RATE_HZ,
                                                            TAIL_S, herzog_leonard_measured)
from neuromuscle.measured import write_measured
from neuromuscle.reports.outdir import refuse_existing_file

#: The shared real-data folder beside the checkout (../shared/real_data), as the tests find it.
REAL_DATA = Path(__file__).resolve().parents[1].parent / "shared" / "real_data"
FOLDER = "cat_soleus_herzog_leonard_2002"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="measured-data HDF5 file to write")
    ap.add_argument("--real-data", default=str(REAL_DATA), help=f"the real-data folder holding {FOLDER}/")
    ap.add_argument("--figures", default=",".join(DEFAULT_FIGURES), help="comma-separated source figures")
    ap.add_argument("--shift-mm", type=float, default=LENGTH_SHIFT_MM, help="model Xm = paper mm + shift (mm)")
    ap.add_argument("--rate-hz", type=float, default=STIMULUS_RATE_HZ, help="stimulation rate (Hz)")
    ap.add_argument("--tail-s", type=float, default=TAIL_S, help="window end after the last stimulus (s)")
    ap.add_argument("--overwrite", action="store_true", help="replace --out if it exists")
    args = ap.parse_args(argv)
    try:
        refuse_existing_file(args.out, args.overwrite)
        data = herzog_leonard_measured(Path(args.real_data) / FOLDER,
                                       figures=[f.strip() for f in args.figures.split(",") if f.strip()],
                                       shift_mm=args.shift_mm, rate_hz=args.rate_hz, tail_s=args.tail_s)
        write_measured(args.out, data, overwrite=args.overwrite)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    pre = data.extra_attrs["/preprocessing"]
    print(f"wrote {args.out}: {len(data.trials)} trials; passive {pre['passive_fit']}")
    for tid, t in data.trials.items():
        s = t.stimulus_times_s
        print(f"  {tid:14s} {t.protocol:9s} peak force {np.max(t.force):6.2f} N, {s.size} stimuli "
              f"{s[0]:.3f}-{s[-1]:.3f} s, passive force enhancement {t.attrs['passive_force_enhancement_N']:.2f} N")
    return 0


if __name__ == "__main__":
    sys.exit(main())
