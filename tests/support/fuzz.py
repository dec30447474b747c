"""How many examples a fuzz test draws: its CI count (the same examples every run, see
tests/conftest.py) times ``FLEXGEAR_FUZZ_SCALE`` (default 1). ``make fuzz`` runs the fuzz
tests with a larger scale and fresh random examples."""
import os


def examples(ci_count: int) -> int:
    return ci_count * max(1, int(os.environ.get("FLEXGEAR_FUZZ_SCALE", "1")))


def number_paths(node, names, prefix=()):
    """Paths (tuples of keys and indices) to every positive finite number of a TOML tree
    stored under a key in ``names``."""
    if isinstance(node, dict):
        for k, v in node.items():
            if k in names and isinstance(v, (int, float)) and not isinstance(v, bool) and 0 < v < float("inf"):
                yield prefix + (k,)
            else:
                yield from number_paths(v, names, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from number_paths(v, names, prefix + (i,))


def at(tree, path):
    """The node of a TOML tree at ``path`` (a tuple of keys and indices)."""
    for step in path:
        tree = tree[step]
    return tree


def tree_paths(node, prefix=()):
    """Every path (tuple of keys and indices) to a leaf or table of a TOML tree."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield prefix + (k,)
            yield from tree_paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield prefix + (i,)
            yield from tree_paths(v, prefix + (i,))
