"""A user's part read from its file, once per process: :func:`part_geometry` picks the reader
of its kind (a CAD file: :mod:`fe_components.part.cad`, OpenCASCADE; a mesh file:
:mod:`fe_components.part.mesh`, meshio), memoises the
:class:`~fe_components.part.geometry.PartGeometry` on the file's content hash and the rules,
and logs what a mesh file held and what was left out (:func:`report_read`).
"""
from __future__ import annotations

import functools
import logging

from . import cad, mesh
from .cells import ReadSummary, counts_text
from .file import PartFile
from .geometry import PartGeometry

log = logging.getLogger(__name__)


#: What a linear mesh costs, measured (tests/fe_components/test_part_order.py): a free steel
#: beam 300 x 10 x 10 mm, 5 mm tetrahedra (2 through the thickness), first bending frequency
#: 762.3 Hz as P1 against 588.4 Hz for the same mesh lifted to P2: +30 %.
P1_STIFFER = 30  # %


def report_read(summary: ReadSummary) -> None:
    """Log what a mesh file held: a WARNING when cells that are not the solid's boundary tags
    were left out (shells, beams, masses ...) or when linear tetrahedra run as P1 unasked;
    else INFO."""
    text = f"{summary.file}: {summary.text()}"
    level = logging.INFO
    if summary.left_out:
        text += f". Left out of the model (only tetrahedra are read): {counts_text(summary.left_out)}"
        level = logging.WARNING
    if summary.order == 1 and not summary.linear_ok:
        text += (f". Linear tetrahedra (P1) are too stiff in bending (first bending frequency +{P1_STIFFER} % "
                 "against P2 on a beam two elements thick; the error falls as h^2): set order = 2 in the "
                 "component table to lift the mesh to P2, or order = 1 to keep it linear")
        level = logging.WARNING
    log.log(level, "%s", text)


@functools.lru_cache(maxsize=32)
def _geometry(part: PartFile) -> PartGeometry:
    geo = (mesh if part.is_mesh else cad).read_part_geometry(part)
    if geo.read is not None:
        report_read(geo.read)
    return geo


def part_geometry(part: PartFile) -> PartGeometry:
    """The part read from its file (memoised per process on its content hash and rules)."""
    return _geometry(part)
