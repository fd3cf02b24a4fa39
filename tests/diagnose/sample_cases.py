"""The diagnosis's CI sample: one blind preparation per measured world, each on a subset of its world's protocol set
(the trials that calibrate the baseline and those that show its causes), so that the sample runs in minutes: world
A's is a null (its cause is the world's own eq 18), A-reduced's holds a staircase, B-reduced's two hidden causes
(staircase and relaxation rate, on the reduced design alone) and B's a staircase.  The sample is a regression check
of the pipeline on fixed files, not a rate: the rates over whole files are the benchmark's (``neuromuscle bench
diagnose --suite``, docs/validation/diagnosis.md).  With the slow tests: a null of world B-reduced, B-reduced's
relaxation alone, "B doublet" and a two-effect file of world B's extended design."""

from __future__ import annotations

from neuromuscle.diagnose.diagnosis import diagnose_data
from neuromuscle.synth import make_dataset, without_truth

#: Twitches and 40 Hz trains at three lengths, 3-20 Hz trains at the optimum (the reduced set) ...
CORE_REDUCED = ("twitch_short", "twitch_opt", "twitch_long", "train4_opt", "train10_opt", "train20_opt", "train40_opt",
                "train40_short", "train40_long", "low_rate3_opt", "low_rate6_opt")
#: ... and 10-100 Hz trains at three lengths (the extended set); its 3 Hz train (4.2 s, the longest) where a cause
#: shows in it.
CORE_EXTENDED = ("twitch_short", "twitch_opt", "twitch_long", "train10_opt", "train20_opt", "train40_opt",
                 "train100_opt", "train10_short", "train40_short", "train10_long", "train40_long")
LOW_RATE = ("train3_opt",)
DOUBLETS = ("doublet5_opt", "doublet10_opt", "doublet15_opt")

#: name -> (first cause or None, further causes {name: strength}, world, trials)
CASES = {
    "A-reduced staircase": ("staircase", {}, "A-reduced", CORE_REDUCED),
    "B-reduced relaxation": ("relaxation_rate", {}, "B-reduced", CORE_REDUCED),
    "B doublet": ("doublet_potentiation", {}, "B", CORE_EXTENDED + LOW_RATE + DOUBLETS),
    "A null": (None, {}, "A", CORE_EXTENDED + DOUBLETS),
    "B-reduced null": (None, {}, "B-reduced", CORE_REDUCED),
    "B staircase and doublet": ("staircase", {"doublet_potentiation": 0.7}, "B",
                                CORE_EXTENDED + LOW_RATE + DOUBLETS + ("twitch_series1_opt", "twitch_series2_opt")),
    "B-reduced staircase and relaxation": ("staircase", {"relaxation_rate": 0.7}, "B-reduced", CORE_REDUCED),
    "B staircase": ("staircase", {}, "B", CORE_EXTENDED + LOW_RATE),
}
STRENGTH, SEED, NOISE_PCT = 0.7, 101, 1.5


def diagnose_case(name: str):
    """The blind diagnosis (one worker) of sample case ``name``."""
    cause, also, world, trials = CASES[name]
    data = make_dataset(cause, STRENGTH, SEED, noise_pct=NOISE_PCT, world=world, trials=list(trials),
                        also=also or None)
    return diagnose_data(without_truth(data), workers=1)
