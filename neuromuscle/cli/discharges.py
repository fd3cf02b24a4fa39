"""``neuromuscle discharges FILE --out DIR``: force from recorded motor-unit discharges, calibrated on the first part
of the trial and predicted on the rest, by Kim muscle units fitted to human motor units and by a fitted twitch sum."""

from __future__ import annotations

import argparse


def add_parser(sub: argparse._SubParsersAction) -> None:
    dp = sub.add_parser("discharges",
                        help="force from recorded motor-unit discharges (Caillet .mat, openhdemg files): calibrate, "
                             "predict the held-out rest, write discharges.h5, .png and .json")
    dp.add_argument("file", help="recording: a Caillet .mat file or a file openhdemg opens (see --format)")
    dp.add_argument("--out", required=True, help="output directory")
    dp.add_argument("--format", default="auto",
                    choices=("auto", "caillet", "openhdemg-json", "openhdemg-otb", "openhdemg-demuse"),
                    help="input format (auto: openhdemg JSON for .json, Caillet for .mat)")
    dp.add_argument("--level", type=float, default=None,
                    help="contraction level (%% MVC) of the plateau, to normalise a raw force (default: from a "
                         "Caillet file name; openhdemg forces are taken as %% MVC)")
    dp.add_argument("--calibration-fraction", type=float, default=0.5,
                    help="share of the contraction (from rest to rest) fitted on (default 0.5); the rest is held out")
    dp.add_argument("--dt-ms", type=float, default=0.05, help="fixed step of the muscle units (ms)")
    dp.add_argument("--overwrite", action="store_true", help="replace an existing report in --out")
    dp.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..pool.discharge_force import run_discharges

    s = run_discharges(args.file, args.out, fmt=args.format, level_percent_mvc=args.level,
                       calibration_fraction=args.calibration_fraction, dt_ms=args.dt_ms, overwrite=args.overwrite)
    h, r = s["human_units"], s["twitch_sum"]
    print(f"{s['file']}: {s['units']} units, {s['duration_ms'] / 1000.0:.1f} s, calibrated on the first "
          f"{100.0 * s['calibration_fraction']:.0f} %")
    print(f"human units: S0 {h['S0']:.3g}, RS {h['RS']:.3g}, RP {h['RP']:.3g}, W {h['W']:.3g}, delay "
          f"{h['delay_ms']:.0f} ms; NRMSE "
          f"calibration {h['nrmse_calibration_percent']:.2f} %, held-out {h['nrmse_heldout_percent']:.2f} %")
    print(f"twitch sum:  RP {r['RP']:.3g}, TL {r['TL_ms']:.3g} ms, RT {r['RT']:.3g}, delay {r['delay_ms']:.0f} ms; "
          f"NRMSE calibration {r['nrmse_calibration_percent']:.2f} %, held-out {r['nrmse_heldout_percent']:.2f} %")
    print(f"wrote {args.out}/discharges.h5, discharges.png and discharges.json")
    return 0
