"""How many examples a fuzz test draws: its CI count (the same examples every run, see
tests/conftest.py) times ``FLEXGEAR_FUZZ_SCALE`` (default 1). ``make fuzz`` runs the fuzz
tests with a larger scale and fresh random examples."""
import os


def examples(ci_count: int) -> int:
    return ci_count * max(1, int(os.environ.get("FLEXGEAR_FUZZ_SCALE", "1")))
