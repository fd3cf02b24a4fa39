"""Packages are found, not listed: every ``neuromuscle*`` folder, plus ``mod/`` shipped as ``neuromuscle._mod``
(mod/ stays at the top level so that ``nrnivmodl mod`` works for hoc users)."""

from setuptools import find_packages, setup

setup(packages=find_packages(include=["neuromuscle", "neuromuscle.*"]) + ["neuromuscle._mod"],
      package_dir={"neuromuscle._mod": "mod"})
