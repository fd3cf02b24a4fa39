"""Hatze's excitation dynamics and the human triceps surae model of van Zandwijk et al. 1998 (an exact Python
integration, the reference for the NEURON mechanisms).

Modules (the tables, Tables 1-4, are :mod:`neuromuscle.model.hatze_parameters`): ``excitation`` (eqs 6-10),
``contraction`` (CE/SEE/PEE, eqs 1-2),
``twitch_fit`` (twitch fit by Levenberg-Marquardt with sensitivity equations), ``scc`` (self-consistent
calculation, eqs 3-4). SI units throughout: s, rad, N m.
"""
