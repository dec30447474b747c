"""``flexgear export elastodyn``: the two-mass drivetrain of a scene as an OpenFAST
ElastoDyn input fragment.

The value lines follow ElastoDyn's primary input file: the value right-aligned in 11
characters, three spaces, the name in 12, then ``- description (unit)``, under the
section lines ``MASS AND INERTIA`` (GenIner) and ``DRIVETRAIN`` (GBRatio, DTTorSpr), with
the descriptions of the NREL 5 MW ElastoDyn file (Jonkman et al. (2009),
NREL/TP-500-38060). Comment lines start with ``!``. Numbers are written to 10 significant digits (read
back to 5e-10 relative: far below any drivetrain datum, and readable where ``repr`` of a
ratio 96.354 would print 96.35416666666677). DTTorDmp is written when the scene's
damping acts on the drivetrain's torsion (:mod:`assembly.analysis.two_mass`);
otherwise the header says why it is not
derived. ``--out`` (:func:`write_fragment`) replaces only a fragment flexgear wrote (its first
line, :data:`HEADER`), never another file, a folder or a symbolic link.
"""
from __future__ import annotations

import logging
import re
from importlib import metadata

from ...analysis.drivetrain import TwoMass
from ...atomic_file import write_text_atomic

log = logging.getLogger(__name__)

#: ElastoDyn's width of a section line.
SECTION_WIDTH = 80
#: The first line of every fragment (then the scene's name): ``--out`` replaces only a file that
#: starts so, i.e. one flexgear wrote.
HEADER = re.compile(r"! flexgear \S*: ElastoDyn drivetrain fragment of scene ")


def flexgear_version() -> str:
    """The installed flexgear version, or "unknown" when it is not installed."""
    try:
        return metadata.version("flexgear")
    except metadata.PackageNotFoundError:
        return "unknown"


def _section(title: str) -> str:
    return f"{'-' * 22} {title} ".ljust(SECTION_WIDTH, "-")


def _value(value: float, name: str, description: str) -> str:
    return f"{float(value):>11.10g}   {name:<12}- {description}"


def values(tm: TwoMass) -> dict[str, float]:
    """ElastoDyn name -> value (SI: -, kg m^2, N m/rad, N m s/rad) of the two-mass equivalent
    (DTTorDmp only with damping)."""
    out = {"GenIner": tm.generator_inertia, "GBRatio": tm.gear_ratio, "DTTorSpr": tm.stiffness}
    if tm.damping:          # None: no damping; 0: the scene's dampers do not act on the torsion
        out["DTTorDmp"] = tm.damping
    return out


def _damping_line(tm: TwoMass) -> str:
    if tm.damping is None:
        return "DTTorDmp not derived: the scene has no damping (keep the value of your turbine model)"
    if not tm.damping:
        return ("DTTorDmp not derived: the scene's dampers do not act on the drivetrain's torsion (e.g. "
                "bearing dampers only); keep the value of your turbine model")
    return ("DTTorDmp = damping matrix condensed with the stiffness's static condensation onto the rotor and "
            "generator rotations, on the low-speed side, plus 2 zeta omega_1 J_eq of the two-mass mode for "
            "modal ratios and Rayleigh damping")


def fragment_text(tm: TwoMass, scene_name: str, version: str | None = None) -> str:
    """The ElastoDyn fragment of ``tm`` (see the module docstring), with a header naming
    the scene, the flexgear version, how each value was derived and the two-mass
    frequencies."""
    f_free, f_locked = tm.frequencies_hz()
    sense = "opposite to" if tm.speed_ratio < 0 else "in the same sense as"
    v = values(tm)
    header = [
        f"flexgear {version or flexgear_version()}: ElastoDyn drivetrain fragment of scene {scene_name!r}",
        f"Two-mass equivalent of the torsional model, rotor body {tm.rotor!r}, generator body {tm.generator!r}:",
        f"GBRatio  = |omega_generator / omega_rotor| from the rigid-body mode (gear geometry); the generator "
        f"turns {sense} the rotor (signed ratio {tm.speed_ratio:.10g})",
        f"GenIner  = generator body {tm.generator_only_inertia:.6g} kg m^2 + the rest of the chain (gears, "
        f"carriers, planets, couplings) reflected to the generator speed {tm.gearbox_inertia:.6g} kg m^2",
        "DTTorSpr = stiffness matrix condensed statically onto the rotor and generator rotations (every mesh, "
        "shaft and bearing between them), on the low-speed side",
        _damping_line(tm),
        f"rotor body inertia J_R = {tm.rotor_inertia:.6g} kg m^2 (not written: ElastoDyn takes it from blades and hub)",
        f"two-mass frequencies: free-free {f_free:.6g} Hz, generator locked {f_locked:.6g} Hz",
    ]
    lines = [f"! {h}" for h in header]
    lines += [_section("MASS AND INERTIA"),
              _value(v["GenIner"], "GenIner", "Generator inertia about HSS (kg m^2)"),
              _section("DRIVETRAIN"),
              _value(v["GBRatio"], "GBRatio", "Gearbox ratio (-)"),
              _value(v["DTTorSpr"], "DTTorSpr", "Drivetrain torsional spring (N-m/rad)")]
    if "DTTorDmp" in v:
        lines.append(_value(v["DTTorDmp"], "DTTorDmp", "Drivetrain torsional damper (N-m/(rad/s))"))
    return "\n".join(lines) + "\n"


def is_fragment(path) -> bool:
    """Whether the file ``path`` starts with the fragment's first line (:data:`HEADER`)."""
    with open(path, "rb") as fh:
        first = fh.readline(4096).decode("utf-8", "replace")
    return HEADER.match(first) is not None


def write_fragment(path, tm: TwoMass, scene_name: str) -> str:
    """Write the fragment to ``path`` atomically; returns its text. A file already there is
    replaced only if it is an earlier fragment (:func:`is_fragment`), and never through a
    symbolic link: :class:`~assembly.app.output.OutputDirError` otherwise."""
    from ..output import check_own_file

    text = fragment_text(tm, scene_name)
    check_own_file(path, is_fragment, "an ElastoDyn fragment flexgear wrote (first line '! flexgear <version>: "
                                      "ElastoDyn drivetrain fragment of scene ...')")
    write_text_atomic(path, text)
    log.info("wrote %s", path)
    return text
