"""Report writers and the output helpers they share: refuse-to-overwrite and atomic writes (``outdir``), one
figure style (``figures``), Markdown tables and numbers (``markdown``); ``fit`` is the ``neuromuscle fit`` report."""
