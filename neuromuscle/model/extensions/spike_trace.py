"""The closed form of a per-spike saturating trace, shared by the extensions' SciPy twins (not an extension).

    dX/dt = -X / tau                      between spikes (ms)
    X -> X + inc_i (1 - X)                at spike i (inc_i in [0, 1], 1 per spike)

is what every event-driven state of the catalogue does (fatigue's depletion D, the staircase, the doublet
facilitation, the post-activation potentiation): ``SpikeTrace`` gives X just before and just after each spike,
and X(t) between them, exactly (no integration).
"""

from __future__ import annotations

import numpy as np


class SpikeTrace:
    """X(t) of a saturating per-spike trace: spikes (ms, increasing), increments (1, one per spike or a scalar),
    decay time constant tau_ms (ms).  ``before[i]``/``after[i]``: X just before/after spike i."""

    def __init__(self, spikes_ms: np.ndarray, increments: np.ndarray | float, tau_ms: float) -> None:
        self.spikes = np.asarray(spikes_ms, dtype=float)
        inc = np.broadcast_to(np.asarray(increments, dtype=float), self.spikes.shape)
        self.tau = float(tau_ms)
        self.before = np.empty(self.spikes.size)
        self.after = np.empty(self.spikes.size)
        x, last = 0.0, 0.0
        for i, ts in enumerate(self.spikes):
            x *= np.exp(-(ts - last) / self.tau)
            self.before[i] = x
            x += inc[i] * (1.0 - x)
            self.after[i], last = x, ts

    def __call__(self, t_ms: float) -> float:
        """X at t_ms (ms); a spike at exactly t_ms counts as delivered."""
        i = int(np.searchsorted(self.spikes, t_ms, side="right")) - 1
        return 0.0 if i < 0 else float(self.after[i] * np.exp(-(t_ms - self.spikes[i]) / self.tau))
