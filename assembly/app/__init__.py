"""flexgear application layer: command line, report pipeline, rendering, plots, design studies,
benchmarks. The model core (:mod:`assembly`) never imports it.

From Python, :func:`run_report` does what ``flexgear run`` does. This module imports nothing
heavy: the command line starts from here.
"""
from __future__ import annotations

__all__ = ["run_report"]


def run_report(scene, out, *, progress: bool = False, **options):
    """Run the ``flexgear run`` pipeline on ``scene`` (a :class:`~assembly.scene.tables.Scene`, a
    scene file or the name of a shipped example) into the folder ``out`` (replaced as a
    whole when the run succeeds, never half-written) and return the run's context
    (:class:`~assembly.app.report.pipeline.RunContext`: ``scene``, ``model``, ``result``,
    ``comparison``, ``files``, ``timings``; ``out_dir``).

    ``options`` are those of :class:`~assembly.app.report.pipeline.RunOptions`: ``n_modes``
    (elastic modes drawn, default 12), ``animated_modes`` (how many of those in the band are
    also animated GIFs, default 3), ``compare`` (torsional vs rigid vs flexible table),
    ``images`` (mode-shape PNGs and GIFs), ``window_size`` (pixels). ``progress``: progress bars on
    stderr."""
    import dataclasses

    from .. import arguments
    from ..scene.tables import Scene
    from .progress import Progress
    from .report.pipeline import RunOptions, run_pipeline

    if not isinstance(scene, Scene):
        arguments.file_path("scene", scene)
    arguments.file_path("out", out)
    arguments.flag("progress", progress)
    known = [f.name for f in dataclasses.fields(RunOptions)]
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise arguments.unknown(unknown[0], options[unknown[0]], known, "option")
    for name in set(options) & {"n_modes", "animated_modes"}:
        arguments.integer(name, options[name], 0)
    for i, n in enumerate(arguments.optional(arguments.instance, "mode_numbers", options.get("mode_numbers"),
                                             (list, tuple), "a list of mode numbers") or ()):
        arguments.integer(f"mode_numbers[{i}]", n, 1)
    for name in set(options) & {"compare", "images"}:
        arguments.flag(name, options[name])
    if "window_size" in options:
        size = options["window_size"]
        if not isinstance(size, (list, tuple)) or len(size) != 2:
            raise arguments.refuse("window_size", size, "must be (width, height) in pixels")
        for i, n in enumerate(size):
            arguments.integer(f"window_size[{i}]", n, 1)
    return run_pipeline(scene, out, RunOptions(**options), Progress(enabled=None if progress else False))
