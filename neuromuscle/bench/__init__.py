"""Benchmarks (``neuromuscle bench unit | fit``): timing code only.  Every default run finishes in about two
minutes on a 2-core machine; ``--full`` gives the long form."""
