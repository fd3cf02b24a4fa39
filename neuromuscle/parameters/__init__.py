"""Parameters: the registry of every component's parameters (units, physiological bounds) and parameter sets."""

from .sets import ParameterSet, builtin_sets, load_parameters, parameters_from_json
from .specs import ParameterSpec, Registry, kim_parameter_names, registry


def __getattr__(name: str) -> object:
    # SPECS is built from the components on first use (not at import: the components import this package)
    if name == "SPECS":
        return registry()
    raise AttributeError(name)


__all__ = ["ParameterSet", "ParameterSpec", "Registry", "SPECS", "builtin_sets", "kim_parameter_names",
           "load_parameters", "parameters_from_json", "registry"]
