"""Diagnosis of measured data (shared/spec/diagnosis.md): what the simulation gets wrong, why, and the held-out gain
of the extension that fixes it.

Modules, one step each: ``split`` (calibration / held-out trials), ``baseline`` (steps 1-2: calibration without
eq 18 and eqs 19-20, every trial's error), ``residuals`` (step 3: explanatory variables, A(t) by inversion, noise),
``candidates`` (step 3: canonical causes, telling trials, ranking, untestable causes), ``extension_fit`` (step 4:
a catalogue extension fitted on calibration trials), ``verdict`` (step 5: the decision rule in numbers),
``diagnosis`` (steps 1-5 in memory), ``report`` (diagnosis.json, report.md, figures, params.json).
"""

from .diagnosis import Diagnosis, diagnose_data
from .report import REPORT_FILES, SCHEMA, run_diagnosis, write_report

__all__ = ["Diagnosis", "REPORT_FILES", "SCHEMA", "diagnose_data", "run_diagnosis", "write_report"]
