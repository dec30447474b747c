"""Benchmarks (``flexgear bench``, ``make bench``): each prints a table of sizes, times,
errors and memory against its peer or floor; none is a test."""
