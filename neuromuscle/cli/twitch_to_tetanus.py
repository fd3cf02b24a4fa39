"""``neuromuscle twitch-to-tetanus``: the workflow of van Zandwijk et al. 1998 (twitch fit, train predictions, trend,
rise times)."""

from __future__ import annotations

import argparse


def add_parser(sub: argparse._SubParsersAction) -> None:
    tt = sub.add_parser("twitch-to-tetanus",
                        help="the workflow of van Zandwijk et al. 1998: fit theta to a twitch, predict trains, trend "
                             "fits, rise times")
    tt.add_argument("--out", default="out/twitch_to_tetanus", help="output directory (report.json, report.md, PNGs)")
    tt.add_argument("--subject", default="3", help="Table 1 subject (1-4) of the twitch")
    tt.add_argument("--twitch-csv", default=None,
                    help="measured twitch: CSV with columns time_s, moment_nm (default: synthetic twitch)")
    tt.add_argument("--stim-time-s", type=float, default=0.02, help="stimulus time of the twitch (s)")
    tt.add_argument("--noise-nm", type=float, default=0.05, help="noise of the synthetic twitch (N m)")
    tt.add_argument("--seed", type=int, default=0, help="seed of the synthetic twitch's noise")
    tt.add_argument("--max-evaluations", type=int, default=200, help="Levenberg-Marquardt evaluations")
    tt.add_argument("--overwrite", action="store_true", help="replace an existing report in --out")
    tt.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..hatze.workflow import run_twitch_to_tetanus

    rep = run_twitch_to_tetanus(args.out, subject=args.subject, twitch_csv=args.twitch_csv, noise_nm=args.noise_nm,
                                seed=args.seed, stim_time_s=args.stim_time_s, overwrite=args.overwrite,
                                max_evaluations=args.max_evaluations)
    fit = rep["fit"]
    print(f"twitch ({rep['twitch']['source']}, subject {rep['twitch']['subject']}): rms residual "
          f"{fit['rms_residual_nm']:.4f} N m after {fit['n_evaluations']} evaluations; trend m (subject 3) "
          f"{rep['trend']['subjects']['3']['m_per_s']:.2f} 1/s (Table 3: 7.94)")
    print(f"wrote {args.out}/report.json, report.md and figures")
    return 0
