"""Analysis of force traces and identification of Module 3: summary metrics and NRMSE (``metrics``, eq 17),
closed-form coefficients (``closed_form``, eqs 13-16 and 18), the inverse of Module 3 (``inverse``) and the one
statement of Module 3's equations (``module3``, eqs 9-12)."""

from .closed_form import hill_mashima_coefficients, length_compensation_coefficients
from .inverse import inverse_activation
from .metrics import Twitch, nrmse_percent, plateau, twitch_metrics

__all__ = ["Twitch", "hill_mashima_coefficients", "inverse_activation", "length_compensation_coefficients",
           "nrmse_percent", "plateau", "twitch_metrics"]
