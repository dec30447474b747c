"""Scene variants for tests: a TOML file that ``extends`` a base scene and changes fields by
path under ``[set]`` (:mod:`assembly.scene.variant`)."""
import json
from pathlib import Path


def write_variant(path: Path, base: Path, changes: dict) -> Path:
    """Write ``path`` extending ``base`` with ``changes`` ({scene path: number or list of
    numbers}); returns ``path``."""
    lines = [f"extends = {json.dumps(str(base))}", "[set]"]
    lines += [f"{json.dumps(k)} = {json.dumps(v)}" for k, v in changes.items()]
    path.write_text("\n".join(lines) + "\n")
    return path
