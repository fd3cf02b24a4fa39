"""Errors raised by neuromuscle: every bad input is reported before NEURON runs, naming the culprit."""


class NeuromuscleError(Exception):
    """Base class for neuromuscle errors."""


class InputError(NeuromuscleError, ValueError):
    """A parameter, protocol, spike train, length trace or data file is invalid.

    The message names the offending item (parameter name, file, trial, field) and the rule it breaks.
    """


class NumericalError(NeuromuscleError, RuntimeError):
    """The integration met trouble it cannot hide: non-finite state, step too large for stability."""


class MechanismBuildError(NeuromuscleError, RuntimeError):
    """nrnivmodl failed to compile the mechanisms; the message carries its output."""
