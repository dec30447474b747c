"""flexgear application layer: command line, report pipeline, rendering, plots, design studies,
benchmarks. The model core (:mod:`assembly`) never imports it.

From Python, :func:`run_report` does what ``flexgear run`` does. This module imports nothing
heavy: the command line starts from here.
"""
from __future__ import annotations

__all__ = ["run_report"]


def run_report(scene, out, *, progress: bool = False, **options):
    """Run the ``flexgear run`` pipeline on ``scene`` (a :class:`~assembly.scene.Scene`, a
    scene file or the name of a shipped example) into the folder ``out`` (replaced as a
    whole when the run succeeds, never half-written) and return the run's context
    (:class:`~assembly.app.pipeline.RunContext`: ``scene``, ``model``, ``result``,
    ``comparison``, ``files``, ``timings``; ``out_dir``).

    ``options`` are those of :class:`~assembly.app.pipeline.RunOptions`: ``n_modes``
    (elastic modes drawn, default 12), ``compare`` (torsional vs rigid vs flexible table),
    ``images`` (mode-shape PNGs), ``window_size`` (pixels). ``progress``: progress bars on
    stderr."""
    import dataclasses

    from .pipeline import RunOptions, run_pipeline
    from .progress import Progress

    known = [f.name for f in dataclasses.fields(RunOptions)]
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise TypeError(f"run_report: unknown option {unknown[0]!r}; options: {', '.join(known)}")
    return run_pipeline(scene, out, RunOptions(**options), Progress(enabled=None if progress else False))
