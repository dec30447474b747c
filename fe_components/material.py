"""Isotropic linear-elastic material (SI units)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from .errors import MaterialError


@dataclass(frozen=True)
class Material:
    """Isotropic linear-elastic material.

    E : Young's modulus [Pa]; nu : Poisson's ratio [-]; rho : density [kg/m^3].
    The defaults are structural steel.
    """

    E: float = 2.1e11
    nu: float = 0.3
    rho: float = 7850.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.E) and self.E > 0):
            raise MaterialError("E", self.E, "Young's modulus must be > 0 Pa")
        if not (math.isfinite(self.nu) and -1.0 < self.nu < 0.5):
            raise MaterialError("nu", self.nu, "Poisson's ratio must satisfy -1 < nu < 0.5")
        if not (math.isfinite(self.rho) and self.rho > 0):
            raise MaterialError("rho", self.rho, "density must be > 0 kg/m^3")

    @property
    def G(self) -> float:
        """Shear modulus [Pa]."""
        return self.E / (2.0 * (1.0 + self.nu))


#: Structural steel, E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3.
STEEL = Material()
