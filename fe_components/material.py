"""Isotropic linear-elastic material (SI units)."""
from __future__ import annotations

from dataclasses import dataclass

from .errors import MaterialError
from .fields import check_fields, quantity


@dataclass(frozen=True)
class Material:
    """Isotropic linear-elastic material.

    E : Young's modulus [Pa]; nu : Poisson's ratio [-]; rho : density [kg/m^3].
    The defaults are structural steel.
    """

    E: float = quantity("Pa", 2.1e11, gt=0.0)
    nu: float = quantity("", 0.3, gt=-1.0, lt=0.5)
    rho: float = quantity("kg/m^3", 7850.0, gt=0.0)

    def __post_init__(self) -> None:
        check_fields(self, MaterialError)

    @property
    def G(self) -> float:
        """Shear modulus [Pa]."""
        return self.E / (2.0 * (1.0 + self.nu))


#: Structural steel, E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3.
STEEL = Material()
