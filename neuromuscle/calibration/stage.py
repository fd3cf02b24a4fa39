"""What one calibration stage returns."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..fit import FitResult


@dataclass
class StageResult:
    """One calibration stage: fitted ``values`` (model units), named ``errors`` (RMS, NRMSE, standard errors),
    the ``trials`` (or data points) it used, ``notes``, the reason it was ``skipped`` and its ``fit`` (if any)."""

    stage: str
    values: dict[str, float] = field(default_factory=dict)
    errors: dict[str, float] = field(default_factory=dict)
    trials: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    skipped: str | None = None
    fit: FitResult | None = None

    def summary(self) -> str:
        """Values, errors, data and notes in a few lines."""
        if self.skipped:
            return f"[{self.stage}] skipped: {self.skipped}"
        vals = ", ".join(f"{k} = {v:.6g}" for k, v in self.values.items())
        errs = ", ".join(f"{k} {v:.4g}" for k, v in self.errors.items())
        lines = [f"[{self.stage}] {vals}", f"    errors: {errs}", f"    data: {', '.join(self.trials)}"]
        lines += [f"    note: {n}" for n in self.notes]
        return "\n".join(lines)
