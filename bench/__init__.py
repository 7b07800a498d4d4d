"""CulinaryCut's benchmarks as one package: every benchmark is a module here with a `main()`, registered once in
bench/registry.py (its script, page, JSON, what it measures and how long it takes), and run through one command:

    python -m bench list                      # every benchmark
    python -m bench run NAME [--quick]        # regenerate one (or `all`); --quick: a smoke pass into a temp folder
    python -m bench index                     # docs/benchmarks/README.md from the registry and the JSON files

What the benchmarks share (machine description, interleaved timing, writing a page and its JSON, plots, the
build's binaries) is bench/harness/; what several of them measure with (cc-cut runs, the accuracy study, the smoke
pass's tiny cases) is bench/lib/.
"""
