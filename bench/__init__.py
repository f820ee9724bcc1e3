"""Benchmarks: each module's ``main()`` times a public call against a baseline run in the same process."""
