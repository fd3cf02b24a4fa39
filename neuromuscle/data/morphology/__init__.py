"""Morphologies shipped with the package (SWC): ``small_motoneuron.swc``, a made-up motoneuron-like cell for tests
and examples of reconstructed-cell pools (``neuromuscle.pool.cells``)."""
