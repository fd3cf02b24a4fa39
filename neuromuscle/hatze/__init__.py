"""Hatze's excitation dynamics and the human triceps surae model of seed 000 (SciPy reference implementation).

Modules: ``parameters`` (Tables 1-4), ``excitation`` (eqs 6-10), ``contraction`` (CE/SEE/PEE, eqs 1-2),
``twitch_fit`` (twitch fit by Levenberg-Marquardt with sensitivity equations), ``scc`` (self-consistent
calculation, eqs 3-4). SI units throughout: s, rad, N m.
"""
