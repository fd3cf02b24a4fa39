"""Diagnosis of measured data: what the simulation gets wrong, why, and what the extension that fixes it gains on
trials it never saw.

Modules, one concern each: ``phases`` (what each trial is, described once), ``split`` (calibration and held-out
trials), ``baseline`` (the model without eq 18 and eqs 19-20, calibrated), ``models`` (fitting a model with
extensions), ``residuals`` (noise, explanatory variables, trends at rest), ``causes`` (the catalogue's causes:
telling trials and where each is defined), ``screening`` (which candidates to fit), ``evidence`` (held-out
statistics), ``rules`` (the decision rules as a table), ``selection`` (forward selection of causes),
``diagnosis`` (all steps in memory) and ``report`` (diagnosis.json, report.md, figures, params.json).
"""

from .diagnosis import Diagnosis, diagnose_data
from .report import REPORT_FILES, SCHEMA, run_diagnosis, write_report

__all__ = ["Diagnosis", "REPORT_FILES", "SCHEMA", "diagnose_data", "run_diagnosis", "write_report"]
