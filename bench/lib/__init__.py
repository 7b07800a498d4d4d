"""What several benchmarks measure with: one cc-cut run and its windowed force (cc_cut), the accuracy study's
settings, errors and guard (accuracy), and the smoke pass's tiny cases (quick)."""
