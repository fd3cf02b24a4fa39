"""The numbers behind a candidate's judgement: how much the model with the candidate's extension predicts the
held-out trials better than the model before it, in the units of the trials' noise.

For held-out trial k: SSE0_k, SSE1_k the squared errors (N^2) of the model before and of the candidate's model,
s_k and rho_k its AR(1) noise (:func:`.residuals.noise_level`), n_k samples, n_eff,k = n_k (1 - rho_k)/(1 + rho_k).

* **held-out gain** in noise variances: sum_k (SSE0_k - SSE1_k)/s_k^2, and its chi-square form corrected for the
  autocorrelation: dX2 = sum_k (SSE0_k - SSE1_k)/s_k^2 (1 - rho_k)/(1 + rho_k);
* **BIC penalty** p ln(N_eff) (p: the candidate's parameters, N_eff = sum_k n_eff,k);
* **block bootstrap**: the 5th percentile of the held-out gain over ``N_BOOTSTRAP`` moving-block resamples of the
  per-sample gains (e0^2 - e1^2)/s_k^2 within each trial (blocks of max(4 (1 + rho)/(1 - rho), n/25) samples);
* **excess**: the held-out error above noise, sum_k max(SSE0_k - n_k s_k^2, 0)/s_k^2, and the share of it the
  candidate removes; each trial's gain and excess are kept (``per_trial``), so where a candidate gains can be
  read beside where the error was;
* the same gain, penalty and bootstrap over the **window** where the cause is judged (:mod:`.causes`,
  :mod:`.selection`), each model's residual there measured from its own level (the isometric misfit at a hold's
  length, 0 elsewhere); when the model before already fits the cause's telling trials to noise, the window is
  where its extension acts, and the gain, penalty and bootstrap on those **quiet** telling trials are kept too;
* beside the causes named before it, the part of the held-out chi-square gain that remains **beyond a resize** of
  those causes, one size for each kind of held-out trial (:mod:`.resize`);
* the **calibration** chi-square gain of the candidate's fit over the model before it and its BIC penalty (both
  fitted on that chi-square, so this is a likelihood ratio);
* the **score** that ranks the candidates that pass: held-out dX2 and calibration gain, each less its penalty.  A
  candidate judged by cross-validation over trials is judged against a model before fitted without some trials,
  which predicts the held-out trials worse than the step's model before; its score's held-out term is therefore
  that of its fit on every calibration trial against the step's model before, on the step's held-out trials.

:mod:`.rules` turns these numbers into a decision.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping, NamedTuple, Sequence

import numpy as np

from ..analysis.metrics import nrmse_percent
from .residuals import Noise

N_BOOTSTRAP = 2000
#: A held-out trial is structured when its residual RMS exceeds this many noise sd.
STRUCTURE_RATIO = 1.5


class WindowSamples(NamedTuple):
    """One held-out trial's samples where the cause is judged (``mask``), how they were chosen (``how``: "defined"
    on the cause's telling window, "acts" where the fitted extension changes the force), the trials a hold is
    measured from, and the model before's and the candidate's residual level there (N: a number, or one per
    sample of the mask)."""

    mask: np.ndarray
    how: str
    references: tuple[str, ...] = ()
    level_before_N: float | np.ndarray = 0.0
    level_after_N: float | np.ndarray = 0.0


@dataclass
class Evidence:
    """The numbers of one candidate against the model before it (module docstring), and the rules it failed
    (rule id -> message, filled by :func:`.rules.apply_rules`)."""

    n_parameters: int
    gain: float
    chi2_gain: float
    bic_penalty: float
    bootstrap_p05: float
    excess: float
    nrmse_before: float
    nrmse_after: float
    structured_before: list[str]
    identified: list[str]
    calibration_chi2_gain: float
    calibration_penalty: float
    window_how: str | None = None
    window_chi2_gain: float | None = None
    window_penalty: float | None = None
    window_p05: float | None = None
    window_trials: dict[str, dict[str, Any]] = field(default_factory=dict)
    rest_left: list[str] = field(default_factory=list)
    n_rest: int = 0
    quiet_chi2_gain: float | None = None
    quiet_penalty: float | None = None
    quiet_p05: float | None = None
    quiet_trials: tuple[str, ...] = ()
    baseline_excess: float | None = None
    crossed: tuple[str, ...] = ()
    resize_chi2_gain: float | None = None
    beyond_resize_chi2_gain: float | None = None
    ranking_chi2_gain: float | None = None
    ranking_penalty: float | None = None
    per_trial: dict[str, dict[str, float]] = field(default_factory=dict)
    failed: dict[str, str] = field(default_factory=dict)

    @property
    def excess_removed(self) -> float:
        """The share of the held-out error above noise the candidate removes."""
        return self.gain / self.excess if self.excess > 0 else 0.0

    @property
    def window_excess_removed(self) -> float | None:
        """The share of the error above noise the candidate removes on the held-out trials where it is judged (rule
        R7's trials, whole): None without such a trial or without error above noise on them."""
        trials = [self.per_trial[i] for i in self.window_trials if i in self.per_trial]
        excess = sum(t["excess"] for t in trials)
        return sum(t["gain"] for t in trials) / excess if excess > 0 else None

    @property
    def window_nrmse(self) -> tuple[float, float] | None:
        """The mean NRMSE (%) before and after on the held-out trials where the cause is judged (rule R7's trials);
        None without such a trial."""
        trials = [self.per_trial[i] for i in self.window_trials if i in self.per_trial]
        if not trials:
            return None
        return (float(np.mean([t["nrmse_before"] for t in trials])),
                float(np.mean([t["nrmse_after"] for t in trials])))

    @property
    def share_of_baseline_excess(self) -> float | None:
        """The held-out gain as a share of the baseline's held-out error above noise (None when not known)."""
        return self.gain / self.baseline_excess if self.baseline_excess else None

    @property
    def beyond_resize_share(self) -> float | None:
        """The share of the held-out chi-square gain that remains beyond a resize of the causes named before the
        candidate (:mod:`.resize`); None when none of them can be resized or the gain is not positive."""
        if self.beyond_resize_chi2_gain is None or self.chi2_gain <= 0:
            return None
        return self.beyond_resize_chi2_gain / self.chi2_gain

    @property
    def passed(self) -> bool:
        return not self.failed

    @property
    def score(self) -> float:
        """How well the candidate's model fits the whole file against the model before it, beyond its
        parameters: held-out dX2 less its BIC penalty plus the calibration chi-square gain less its BIC penalty
        (noise variances).  Ranks the candidates that pass every rule.  For a candidate judged by cross-validation
        over trials the held-out term is ``ranking_chi2_gain``: its fit on every calibration trial against the model
        before on the step's own held-out trials, the trials and the model every other candidate is scored on."""
        held, penalty = ((self.chi2_gain, self.bic_penalty) if self.ranking_chi2_gain is None
                         else (self.ranking_chi2_gain, self.ranking_penalty or 0.0))
        return held - penalty + self.calibration_chi2_gain - self.calibration_penalty

    def text(self) -> str:
        """One line: the held-out error, gains against penalties, bootstrap, excess removed, failures."""
        parts = [f"{', '.join(self.crossed)} held out too (cross-validation over trials)"] \
            if self.crossed else []
        parts += [f"held-out mean NRMSE {self.nrmse_before:.2f} -> {self.nrmse_after:.2f} %",
                 f"held-out chi2 gain {self.chi2_gain:.1f} vs BIC penalty {self.bic_penalty:.1f}",
                 f"bootstrap 5th percentile {self.bootstrap_p05:.4g}",
                 f"removes {100 * self.excess_removed:.0f} % of the held-out error above noise",
                 f"calibration chi2 gain {self.calibration_chi2_gain:.1f} vs {self.calibration_penalty:.1f}"]
        if self.window_chi2_gain is not None:
            parts.append(f"where the cause is {'defined' if self.window_how == 'defined' else 'acting'} "
                         f"({len(self.window_trials)} held-out trials) chi2 gain {self.window_chi2_gain:.1f} vs "
                         f"{self.window_penalty:.1f}, bootstrap 5th percentile {self.window_p05:.4g}")
        if self.ranking_chi2_gain is not None:
            parts.append(f"scored on the held-out trials alone with its fit on every calibration trial: chi2 gain "
                         f"{self.ranking_chi2_gain:.1f} vs {self.ranking_penalty:.1f}")
        if self.beyond_resize_chi2_gain is not None:
            parts.append(f"beyond a resize of the causes before it chi2 gain "
                         f"{self.beyond_resize_chi2_gain:.1f} (the resize alone {self.resize_chi2_gain:.1f})")
        parts.append("passes every rule" if self.passed else
                     "FAILS " + "; ".join(f"{k}: {v}" for k, v in self.failed.items()))
        return "; ".join(parts)

    def to_json(self) -> dict[str, Any]:
        return {"n_parameters": self.n_parameters, "gain_noise_variances": self.gain, "chi2_gain": self.chi2_gain,
                "bic_penalty": self.bic_penalty, "bootstrap_p05": self.bootstrap_p05, "excess": self.excess,
                "excess_removed": self.excess_removed, "window_excess_removed": self.window_excess_removed,
                "window_nrmse": self.window_nrmse, "nrmse_heldout_before": self.nrmse_before,
                "nrmse_heldout_after": self.nrmse_after, "structured_before": self.structured_before,
                "identified": self.identified, "calibration_chi2_gain": self.calibration_chi2_gain,
                "calibration_bic_penalty": self.calibration_penalty, "window": self.window_how,
                "window_chi2_gain": self.window_chi2_gain, "window_bic_penalty": self.window_penalty,
                "window_bootstrap_p05": self.window_p05, "window_trials": self.window_trials,
                "quiet_telling_trials": list(self.quiet_trials), "quiet_chi2_gain": self.quiet_chi2_gain,
                "quiet_bic_penalty": self.quiet_penalty, "quiet_bootstrap_p05": self.quiet_p05,
                "rest_trend_trials": self.rest_left, "trials_with_rest": self.n_rest, "score": self.score,
                "baseline_excess": self.baseline_excess, "share_of_baseline_excess": self.share_of_baseline_excess,
                "cross_validated_trials": list(self.crossed),
                "resize_chi2_gain": self.resize_chi2_gain, "beyond_resize_chi2_gain": self.beyond_resize_chi2_gain,
                "ranking_chi2_gain": self.ranking_chi2_gain, "ranking_bic_penalty": self.ranking_penalty,
                "per_trial": self.per_trial, "passed": self.passed, "failed": self.failed}


def block_bootstrap_p05(gains: Sequence[np.ndarray], noise: Sequence[Noise], rng: np.random.Generator,
                        n_boot: int = N_BOOTSTRAP) -> float:
    """5th percentile of the summed per-sample gains under a moving-block bootstrap within each series."""
    total = np.zeros(n_boot)
    for d, nz in zip(gains, noise):
        n = d.size
        if n == 0:
            continue
        block = int(min(n, max(math.ceil(4.0 * (1 + nz.rho) / (1 - nz.rho)), math.ceil(n / 25.0))))
        n_blocks = math.ceil(n / block)
        sums = np.convolve(d, np.ones(block), mode="valid")
        starts = rng.integers(0, sums.size, size=(n_boot, n_blocks))
        total += sums[starts].sum(axis=1) * (n / (n_blocks * block))
    return float(np.quantile(total, 0.05))


def excess(heldout: Sequence[str], measured: Mapping[str, np.ndarray], simulated: Mapping[str, np.ndarray],
           noise: Mapping[str, Noise]) -> float:
    """The held-out error above noise of a model's forces (N), in noise variances: sum_k max(SSE_k - n_k s_k^2, 0)
    / s_k^2."""
    out = 0.0
    for i in heldout:
        e = simulated[i] - measured[i]
        out += max(float(e @ e) / noise[i].sd_N ** 2 - e.size, 0.0)
    return out


def structured_trials(measured: Mapping[str, np.ndarray], simulated: Mapping[str, np.ndarray],
                      noise: Mapping[str, Noise], ids: Sequence[str], ratio: float = STRUCTURE_RATIO) -> list[str]:
    """The trials among ``ids`` whose residual RMS exceeds ``ratio`` times their noise sd."""
    out = []
    for i in ids:
        e = simulated[i] - measured[i]
        if math.sqrt(float(e @ e) / e.size) > ratio * noise[i].sd_N:
            out.append(i)
    return out


def window_residuals(h: WindowSamples, measured: np.ndarray, simulated: np.ndarray, before: bool = True
                     ) -> np.ndarray:
    """One model's residual (N) on a window's samples, measured from that model's level there (``before``: the
    model before's level, else the candidate's)."""
    return (simulated - measured)[h.mask] - (h.level_before_N if before else h.level_after_N)


def quiet_window(window: Mapping[str, WindowSamples], measured: Mapping[str, np.ndarray],
                 before: Mapping[str, np.ndarray], noise: Mapping[str, Noise], ratio: float = STRUCTURE_RATIO
                 ) -> bool:
    """Whether the model before fits every trial of ``window`` to its noise there: residual RMS (from its level)
    at most ``ratio`` noise sd in each.  Such a window has nothing a cause could show."""
    for i, h in window.items():
        e = window_residuals(h, measured[i], before[i])
        if e.size and math.sqrt(float(e @ e) / e.size) > ratio * noise[i].sd_N:
            return False
    return True


def window_judgement(window: Mapping[str, WindowSamples], measured: Mapping[str, np.ndarray],
                     before: Mapping[str, np.ndarray], after: Mapping[str, np.ndarray], noise: Mapping[str, Noise],
                     n_parameters: int, seed: int = 0
                     ) -> tuple[float, float, float | None, dict[str, tuple[int, float]]]:
    """The autocorrelation-corrected chi-square gain of the candidate over the model before on ``window``, its BIC
    penalty (noise variances), the 5th percentile of its block bootstrap (None without samples) and each trial's
    (samples, chi-square gain)."""
    gain = n_eff = 0.0
    samples, noises, per_trial = [], [], {}
    for i, h in window.items():
        if not np.any(h.mask):
            continue
        nz = noise[i]
        e0 = window_residuals(h, measured[i], before[i])
        e1 = window_residuals(h, measured[i], after[i], before=False)
        w = (1 - nz.rho) / (1 + nz.rho)
        d = (e0 ** 2 - e1 ** 2) / nz.sd_N ** 2
        g = float(d.sum()) * w
        gain += g
        n_eff += e0.size * w
        samples.append(d)
        noises.append(nz)
        per_trial[i] = (int(e0.size), g)
    p05 = block_bootstrap_p05(samples, noises, np.random.default_rng(seed)) if samples else None
    return gain, n_parameters * math.log(max(n_eff, 2.0)), p05, per_trial


def heldout_chi2_gain(heldout: Sequence[str], measured: Mapping[str, np.ndarray], before: Mapping[str, np.ndarray],
                      after: Mapping[str, np.ndarray], noise: Mapping[str, Noise], n_parameters: int
                      ) -> tuple[float, float]:
    """dX2 of the model giving ``after`` over the one giving ``before`` (forces in N by trial id) on the ``heldout``
    trials, corrected for the noise's autocorrelation, and its BIC penalty p ln(N_eff) (module docstring)."""
    chi2 = n_eff = 0.0
    for i in heldout:
        e0, e1 = before[i] - measured[i], after[i] - measured[i]
        nz = noise[i]
        v = nz.sd_N ** 2
        s0, s1 = float(e0 @ e0) / v, float(e1 @ e1) / v
        chi2 += (s0 - s1) * (1 - nz.rho) / (1 + nz.rho)
        n_eff += nz.n_eff
    return chi2, n_parameters * math.log(max(n_eff, 2.0))


def gather(heldout: Sequence[str], measured: Mapping[str, np.ndarray], before: Mapping[str, np.ndarray],
           after: Mapping[str, np.ndarray], noise: Mapping[str, Noise], n_parameters: int, identified: list[str],
           calibration: tuple[float, float], window: Mapping[str, WindowSamples] | None, seed: int = 0,
           quiet: Mapping[str, WindowSamples] | None = None) -> Evidence:
    """The evidence of a candidate whose model gives ``after`` against the model before it (``before``), forces in
    N by trial id, on the ``heldout`` trials; calibration: (chi-square gain, BIC penalty) of its fit; window: the
    held-out samples where the cause is judged (None: no such samples); quiet: its telling trials' window when the
    model before fits them to noise and the cause is judged where it acts instead (None otherwise)."""
    gain = excess = 0.0
    per_sample, nr0, nr1, per_trial = [], [], [], {}
    for i in heldout:
        e0, e1 = before[i] - measured[i], after[i] - measured[i]
        v = noise[i].sd_N ** 2
        s0, s1 = float(e0 @ e0) / v, float(e1 @ e1) / v
        gain += s0 - s1
        excess += max(s0 - e0.size, 0.0)
        nr0.append(nrmse_percent(measured[i], before[i]))
        nr1.append(nrmse_percent(measured[i], after[i]))
        per_trial[i] = {"gain": s0 - s1, "excess": max(s0 - e0.size, 0.0), "nrmse_before": nr0[-1],
                        "nrmse_after": nr1[-1]}
        per_sample.append((e0 ** 2 - e1 ** 2) / v)
    chi2, penalty = heldout_chi2_gain(heldout, measured, before, after, noise, n_parameters)
    p05 = block_bootstrap_p05(per_sample, [noise[i] for i in heldout], np.random.default_rng(seed))
    ev = Evidence(n_parameters, gain, chi2, penalty, p05, excess, float(np.mean(nr0)), float(np.mean(nr1)),
                  structured_trials(measured, before, noise, heldout), identified, *calibration, per_trial=per_trial)
    if window:
        _window(ev, window, measured, before, after, noise, seed)
    if quiet:
        ev.quiet_chi2_gain, ev.quiet_penalty, ev.quiet_p05, _ = window_judgement(quiet, measured, before, after,
                                                                                 noise, n_parameters, seed + 2)
        ev.quiet_trials = tuple(quiet)
    return ev


def _window(ev: Evidence, window: Mapping[str, WindowSamples], measured: Mapping[str, np.ndarray],
            before: Mapping[str, np.ndarray], after: Mapping[str, np.ndarray], noise: Mapping[str, Noise],
            seed: int) -> None:
    gain, penalty, p05, per_trial = window_judgement(window, measured, before, after, noise, ev.n_parameters,
                                                     seed + 1)
    if not per_trial:
        return
    for i, (n, g) in per_trial.items():
        h = window[i]
        ev.window_trials[i] = {"samples": n, "chi2_gain": g, "how": h.how, "isometric_references": list(h.references),
                               "level_before_N": float(np.mean(h.level_before_N)),
                               "level_after_N": float(np.mean(h.level_after_N))}
    ev.window_how = "defined" if all(w["how"] == "defined" for w in ev.window_trials.values()) else "acts"
    ev.window_chi2_gain, ev.window_penalty, ev.window_p05 = gain, penalty, p05
