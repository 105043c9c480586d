"""Soil and rock materials: validated, frozen parameter sets in SI units.

Units: E in kPa, unit weight in kN/m3, cohesion and strengths in kPa, angles in degrees,
contact stiffness in kPa/m (normal force per unit thickness = k_n * overlap area).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace

GRAVITY = 9.81  # m/s2, converts unit weight (kN/m3) to density (t/m3)

__all__ = ["GRAVITY", "Material", "MaterialError", "MaterialWarning"]


class MaterialError(ValueError):
    """A material parameter is out of its valid range."""


class MaterialWarning(UserWarning):
    """A material parameter is valid but looks like it was given in the wrong unit."""


@dataclass(frozen=True, kw_only=True)
class Material:
    """A linear-elastic, optionally Mohr-Coulomb perfectly plastic, material.

    Keyword-only (``Material(name="clay", E=10_000.0, nu=0.3, ...)``). A Young's modulus
    below 100 kPa (a modulus in MPa?) or a friction or dilation angle below 1.6 that is not a
    whole number of degrees (an angle in radians?) is accepted with a ``MaterialWarning``.

    A material is plastic when ``plastic=True`` is given or when it has strength parameters
    (``cohesion > 0`` or ``phi > 0``); otherwise it stays elastic however it is loaded.

    Attributes:
        name: label used in error messages and outputs.
        E: Young's modulus [kPa].
        nu: Poisson's ratio [-], 0 <= nu < 0.5.
        unit_weight: gamma [kN/m3] (density = gamma / g [t/m3]).
        cohesion: c [kPa].
        phi: friction angle [deg], 0 <= phi < 90.
        psi: dilation angle [deg], 0 <= psi <= phi (psi = phi is associated flow).
        tensile_strength: tension cut-off [kPa]; None means the Mohr-Coulomb apex c cot(phi).
        interface_cohesion, interface_phi, interface_tensile_strength: strength of the bonds
            between discrete elements (default: the material's own c, phi, tensile strength).
        contact_stiffness: k_n [kPa/m]; None lets the engine pick it from E and element size.
        contact_phi: friction angle of contacts between separated elements [deg]
            (default: phi).
        contact_damping: viscous damping ratio zeta [-] of the normal contact spring
            (0 <= zeta <= 1; 0: none, separated blocks rattle until mass damping stops them).
    """

    name: str
    E: float
    nu: float
    unit_weight: float = 0.0
    cohesion: float = 0.0
    phi: float = 0.0
    psi: float = 0.0
    tensile_strength: float | None = None
    plastic: bool | None = None
    interface_cohesion: float | None = None
    interface_phi: float | None = None
    interface_tensile_strength: float | None = None
    contact_stiffness: float | None = None
    contact_phi: float | None = None
    contact_damping: float = 0.0

    def __post_init__(self) -> None:
        def bad(param: str, value: object, rule: str) -> MaterialError:
            return MaterialError(
                f"material '{self.name}': {param} = {value!r} is invalid; it must be {rule}"
            )

        numbers = {
            "E": self.E, "nu": self.nu, "unit_weight": self.unit_weight,
            "cohesion": self.cohesion, "phi": self.phi, "psi": self.psi,
            "contact_damping": self.contact_damping,
        }
        for key in ("tensile_strength", "interface_cohesion", "interface_phi",
                    "interface_tensile_strength", "contact_stiffness", "contact_phi"):
            if getattr(self, key) is not None:
                numbers[key] = getattr(self, key)
        for key, value in numbers.items():
            if not isinstance(value, int | float) or not math.isfinite(value):
                raise bad(key, value, "a finite number")
        if self.E <= 0:
            raise bad("E", self.E, "> 0 kPa")
        if not 0 <= self.nu < 0.5:
            raise bad("nu", self.nu, "in [0, 0.5) (0.5 is incompressible: use 0.49 at most)")
        if self.unit_weight < 0:
            raise bad("unit_weight", self.unit_weight, ">= 0 kN/m3")
        if self.cohesion < 0:
            raise bad("cohesion", self.cohesion, ">= 0 kPa")
        if not 0 <= self.phi < 90:
            raise bad("phi", self.phi, "in [0, 90) degrees")
        if not 0 <= self.psi <= self.phi:
            raise bad("psi", self.psi, f"in [0, phi = {self.phi}] degrees (dilation <= friction)")
        if self.is_plastic and self.cohesion == 0 and self.phi == 0:
            raise bad("cohesion", self.cohesion, "> 0 or phi > 0 for a plastic material")
        for key in ("tensile_strength", "interface_cohesion", "interface_tensile_strength"):
            value = getattr(self, key)
            if value is not None and value < 0:
                raise bad(key, value, ">= 0 kPa")
        for key in ("interface_phi", "contact_phi"):
            value = getattr(self, key)
            if value is not None and not 0 <= value < 90:
                raise bad(key, value, "in [0, 90) degrees")
        if self.contact_stiffness is not None and self.contact_stiffness <= 0:
            raise bad("contact_stiffness", self.contact_stiffness, "> 0 kPa/m")
        if not 0 <= self.contact_damping <= 1:
            raise bad("contact_damping", self.contact_damping, "a damping ratio in [0, 1]")
        self._warn_units()

    def _warn_units(self) -> None:
        """Warn about values that look like the wrong unit (valid, but suspicious)."""
        if self.E < 100.0:
            warnings.warn(f"material '{self.name}': E = {self.E:g} kPa is very soft; E is in "
                          f"kPa (for {self.E:g} MPa give E = {1000 * self.E:g})",
                          MaterialWarning, stacklevel=4)
        for key in ("phi", "psi", "interface_phi", "contact_phi"):
            value = getattr(self, key)
            if value is not None and 0 < value < 1.6 and value != round(value):
                warnings.warn(f"material '{self.name}': {key} = {value:g} deg; angles are in "
                              f"degrees (if {value:g} is in radians give "
                              f"{math.degrees(value):.4g})", MaterialWarning, stacklevel=4)

    # --- derived quantities -------------------------------------------------------------
    @property
    def is_plastic(self) -> bool:
        """True when the Mohr-Coulomb return is applied."""
        if self.plastic is not None:
            return self.plastic
        return self.cohesion > 0 or self.phi > 0

    @property
    def density(self) -> float:
        """Mass density rho = gamma / g [t/m3]."""
        return self.unit_weight / GRAVITY

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [kPa]."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def bulk_modulus(self) -> float:
        """Plane-strain-independent 3-D bulk modulus K = E / (3 (1 - 2 nu)) [kPa]."""
        return self.E / (3.0 * (1.0 - 2.0 * self.nu))

    @property
    def lame_lambda(self) -> float:
        """lambda = E nu / ((1 + nu)(1 - 2 nu)) [kPa]."""
        return self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))

    @property
    def k0(self) -> float:
        """Elastic at-rest earth-pressure coefficient nu / (1 - nu) (oedometric loading)."""
        return self.nu / (1.0 - self.nu)

    @property
    def p_wave_speed(self) -> float:
        """P-wave speed sqrt((K + 4G/3) / rho) [m/s]; inf for a weightless material."""
        if self.density == 0:
            return math.inf
        return math.sqrt((self.bulk_modulus + 4.0 * self.shear_modulus / 3.0) / self.density)

    def resolved_tensile_strength(self) -> float:
        """Tension cut-off [kPa]: the given value, at most the Mohr-Coulomb apex c cot(phi)
        (the default), as the shared kernel expects.

        For phi = 0 (Tresca) without a given value the cut-off is inactive (a large number).
        """
        apex = self.cohesion / math.tan(math.radians(self.phi)) if self.phi > 0 else 1e30
        if self.tensile_strength is not None:
            return min(float(self.tensile_strength), apex)  # no tension beyond the apex
        return apex

    def mohr_coulomb_row(self) -> tuple[float, ...]:
        """[K, G, c, sin phi, cos phi, sin psi, tensile strength] for the shared kernel."""
        phi, psi = math.radians(self.phi), math.radians(self.psi)
        return (self.bulk_modulus, self.shear_modulus, self.cohesion, math.sin(phi),
                math.cos(phi), math.sin(psi), self.resolved_tensile_strength())

    def weakened(self, factor: float) -> Material:
        """Every strength divided by ``factor`` (strength reduction, Zienkiewicz et al. 1975):
        c / F, tan(phi) / F, tan(psi) / F, tensile strength / F, and the same for the
        interface and contact strengths that are given (those left None follow c and phi).
        ``factor`` < 1 makes the material stronger."""
        if not (isinstance(factor, int | float) and math.isfinite(factor) and factor > 0):
            raise MaterialError(f"material '{self.name}': strength factor {factor!r} must be a "
                                "finite number > 0")

        def angle(value: float | None) -> float | None:
            if value is None:
                return None
            return math.degrees(math.atan(math.tan(math.radians(value)) / factor))

        def divided(value: float | None) -> float | None:
            return None if value is None else value / factor

        phi = angle(self.phi)
        with warnings.catch_warnings():  # reduced angles are degrees, whatever their size
            warnings.simplefilter("ignore", MaterialWarning)
            return replace(self, cohesion=self.cohesion / factor, phi=phi,
                           psi=min(angle(self.psi), phi), plastic=self.is_plastic,
                           tensile_strength=divided(self.tensile_strength),
                           interface_cohesion=divided(self.interface_cohesion),
                           interface_phi=angle(self.interface_phi),
                           interface_tensile_strength=divided(self.interface_tensile_strength),
                           contact_phi=angle(self.contact_phi))
