"""Measured muscle data in the layout of docs/reference/data-format.md (times in s, force in N or N*m,
length in mm or rad): the objects, their validator, HDF5 reading and writing, CSV import and a summary.

``schema`` holds the layout and the objects, ``validate`` every rule (one validator that the reader, the writer,
CSV import and the literature loaders all go through), ``hdf5`` the file, ``csv_import`` the conversion from
CSV, ``summary`` the text report, ``example`` the package's example file. The published data sets are loaded by
:mod:`neuromuscle.literature`.
"""

from .csv_import import import_csv
from .example import example_data, example_path, write_example
from .hdf5 import read_measured, write_measured
from .schema import FORCE_UNITS, LENGTH_UNITS, SCHEMA, MeasuredData, Trial
from .summary import check_file, summarize
from .validate import find_problems, validate_measured

__all__ = ["FORCE_UNITS", "LENGTH_UNITS", "SCHEMA", "MeasuredData", "Trial", "check_file", "example_data",
           "example_path", "find_problems", "import_csv", "read_measured", "summarize", "validate_measured",
           "write_example", "write_measured"]
