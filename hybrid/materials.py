"""Soil and rock materials: one validated, frozen parameter record for both phases.

Units: E in kPa, unit weight in kN/m3, density in t/m3, cohesion and strengths in kPa, angles
in degrees, contact stiffness in kPa/m (normal force per unit thickness = k_n x overlap area).
The Mohr-Coulomb kernel row built from a material is in ``hybrid.constitutive.table``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace
from typing import Any

GRAVITY = 9.81  # m/s2, converts unit weight (kN/m3) to density (t/m3)
#: Default of ``Material.unit_weight`` and ``.density``: whichever is not given follows from
#: the other (both 0 when neither is given).
GIVEN_OR_DERIVED: Any = None

__all__ = ["GRAVITY", "Bond", "Contact", "Material", "MaterialError", "MaterialWarning",
           "Strength"]


class MaterialError(ValueError):
    """A material parameter is out of its valid range."""


class MaterialWarning(UserWarning):
    """A material parameter is valid but looks like it was given in the wrong unit."""


def _invalid(owner: str, param: str, value: object, rule: str) -> MaterialError:
    return MaterialError(f"{owner}: {param} = {value!r} is invalid; it must be {rule}")


def _check_numbers(owner: str, values: dict[str, object]) -> None:
    """Every given value is a finite real number (bool is refused: ``E=True`` is a slip)."""
    for key, value in values.items():
        if value is None:
            continue
        if (isinstance(value, bool) or not isinstance(value, int | float)
                or not math.isfinite(value)):
            raise _invalid(owner, key, value, "a finite number")


def _check_angle(owner: str, key: str, value: float | None) -> None:
    if value is not None and not 0 <= value < 90:
        raise _invalid(owner, key, value, "in [0, 90) degrees")


def _warn_radians(owner: str, key: str, value: float | None) -> None:
    """Warn about an angle below 1.6 that is not a whole number of degrees (radians?)."""
    if value is not None and 0 < value < 1.6 and value != round(value):
        warnings.warn(f"{owner}: {key} = {value:g} deg; angles are in degrees (if {value:g} "
                      f"is in radians give {math.degrees(value):.4g})", MaterialWarning,
                      stacklevel=4)


def _reduced_angle(value: float, factor: float) -> float:
    """The angle whose tangent is tan(value) / factor [deg]."""
    return math.degrees(math.atan(math.tan(math.radians(value)) / factor))


def _reduced_optional(value: float | None, factor: float) -> float | None:
    return None if value is None else _reduced_angle(value, factor)


def _divided(value: float | None, factor: float) -> float | None:
    return None if value is None else value / factor


@dataclass(frozen=True, kw_only=True)
class Strength:
    """Mohr-Coulomb strength (the peak of a material; a residual strength has the same form).

    Attributes:
        cohesion: c [kPa].
        phi: friction angle [deg].
        psi: dilation angle [deg] (psi = phi is associated flow).
        tensile_strength: tension cut-off [kPa]; None means the apex c cot(phi).
    """

    cohesion: float = 0.0
    phi: float = 0.0
    psi: float = 0.0
    tensile_strength: float | None = None

    @property
    def cutoff(self) -> float | None:
        """The tension cut-off in force [kPa]: the given one, at most the apex c cot(phi).

        None: there is none (phi = 0 without a given one).
        """
        if self.phi > 0:
            apex = self.cohesion / math.tan(math.radians(self.phi))
            return apex if self.tensile_strength is None else min(self.tensile_strength, apex)
        return self.tensile_strength


def _weakened_strength(s: Strength, factor: float, cutoff: float | None = None) -> Strength:
    """C / F, tan(phi) / F, tan(psi) / F (at most phi), tensile strength / F.

    The tensile strength at most ``cutoff`` [kPa], the weakened peak's: its apex c cot(phi) is
    the same at any F, so a residual cut-off divided by F < 1 could pass it.
    """
    phi = _reduced_angle(s.phi, factor)
    tensile = _divided(s.tensile_strength, factor)
    if tensile is not None and cutoff is not None:
        tensile = min(tensile, cutoff)
    return Strength(cohesion=s.cohesion / factor, phi=phi,
                    psi=min(_reduced_angle(s.psi, factor), phi), tensile_strength=tensile)


@dataclass(frozen=True, kw_only=True)
class Bond:
    """Strength of the bond between two intact discrete elements (thesis section 4.5).

    A bond breaks in tension beyond ``tensile_strength`` or in shear beyond
    ``cohesion + sigma_n tan(phi)``; then the two elements meet by contact only. Between two
    materials the weaker of the two shear strengths at the interface's normal stress governs,
    and the smaller tensile strength. A value left None follows the material: its own c, phi
    and tension cut-off when it is plastic. An elastic material has no strength, so its bonds
    are unbreakable unless a value is given (a bond to a plastic material then has the
    plastic side's strength).

    Attributes:
        cohesion: bond cohesion [kPa].
        phi: bond friction angle [deg].
        tensile_strength: bond tensile strength [kPa].
    """

    cohesion: float | None = None
    phi: float | None = None
    tensile_strength: float | None = None

    def __post_init__(self) -> None:
        owner = "Bond"
        _check_numbers(owner, {"cohesion": self.cohesion, "phi": self.phi,
                               "tensile_strength": self.tensile_strength})
        for key in ("cohesion", "tensile_strength"):
            value = getattr(self, key)
            if value is not None and value < 0:
                raise _invalid(owner, key, value, ">= 0 kPa")
        _check_angle(owner, "phi", self.phi)
        _warn_radians(owner, "phi", self.phi)


@dataclass(frozen=True, kw_only=True)
class Contact:
    """Contact between separated discrete elements (penalty springs with Coulomb friction).

    Attributes:
        normal_stiffness: k_n [kPa/m] (normal force per unit thickness = k_n x overlap area
            / contact length); None: 10 E / mean element size.
        shear_stiffness: k_t [kPa/m] of the tangential spring; None: equal to k_n.
        phi: contact friction angle [deg]; None: the material's residual phi when it
            softens, else its phi.
        cohesion: shear strength of the contact at zero normal stress [kPa], acting over the
            contact length while the two sides press on each other (a crack's strength
            ``tau <= c + sigma_n tan phi``); None: the material's residual cohesion when it
            softens, else 0. A crack in a softening material so carries the residual
            strength of the band it replaces: in an undrained (phi = 0) clay, its residual
            c_u on any normal stress; in a drained soil (c_r = 0 usually), friction alone.
            Between two materials the weaker of their two strengths at the contact's normal
            force governs (the crack runs through the weaker side). It acts in full as soon
            as two faces press, however lightly: a crack that closes again, or a block that
            lands on another, carries c at once (a total-stress strength does not depend on
            the pressure).
        damping: viscous damping ratio zeta [-] of the normal spring (0 <= zeta <= 1; 0: none,
            separated blocks rattle until mass damping stops them). Above about 0.34 it shortens
            the time step the solver chooses, to keep the damped contacts stable
            (``hybrid.discrete.integrate.damped_contact_step``).
    """

    normal_stiffness: float | None = None
    shear_stiffness: float | None = None
    phi: float | None = None
    cohesion: float | None = None
    damping: float = 0.0

    def __post_init__(self) -> None:
        owner = "Contact"
        _check_numbers(owner, {"normal_stiffness": self.normal_stiffness,
                               "shear_stiffness": self.shear_stiffness, "phi": self.phi,
                               "cohesion": self.cohesion, "damping": self.damping})
        if self.cohesion is not None and self.cohesion < 0:
            raise _invalid(owner, "cohesion", self.cohesion, ">= 0 kPa")
        for key in ("normal_stiffness", "shear_stiffness"):
            value = getattr(self, key)
            if value is not None and value <= 0:
                raise _invalid(owner, key, value, "> 0 kPa/m")
        _check_angle(owner, "phi", self.phi)
        if not 0 <= self.damping <= 1:
            raise _invalid(owner, "damping", self.damping, "a damping ratio in [0, 1]")
        _warn_radians(owner, "phi", self.phi)


@dataclass(frozen=True, kw_only=True)
class Material:
    """A linear-elastic, optionally Mohr-Coulomb perfectly plastic, material of either phase.

    Keyword-only (``Material(name="clay", E=10_000.0, nu=0.3, unit_weight=18.0, ...)``). The
    weight is given as ``unit_weight`` [kN/m3] or as ``density`` [t/m3] (one of them; the
    other follows with g = ``GRAVITY``). A Young's modulus below 100 kPa (a modulus in MPa?)
    or a friction or dilation angle below 1.6 that is not a whole number of degrees (an angle
    in radians?) is accepted with a ``MaterialWarning``.

    A material is plastic when ``plastic=True`` is given or when it has strength parameters
    (``cohesion > 0`` or ``phi > 0``); otherwise it stays elastic however it is loaded.

    Attributes:
        name: label used in error messages and outputs.
        E: Young's modulus [kPa].
        nu: Poisson's ratio [-], 0 <= nu < 0.5.
        unit_weight: gamma [kN/m3] (default 0: weightless, or density x g).
        density: rho [t/m3] (default unit_weight / g).
        cohesion: peak c [kPa].
        phi: peak friction angle [deg], 0 <= phi < 90.
        psi: dilation angle [deg], 0 <= psi <= phi (psi = phi is associated flow).
        tensile_strength: tension cut-off [kPa]; None means the Mohr-Coulomb apex c cot(phi).
        plastic: force (True) or suppress (False) the Mohr-Coulomb return; None: plastic when
            the material has a strength.
        residual: the residual strength (``Strength``) reached by strain softening; None: no
            softening (perfect plasticity at the peak). c, phi and psi at most the peak ones,
            psi at most phi. Its ``tensile_strength``: None keeps the peak's given cut-off (or,
            none given, the apex c cot(phi) of the strength in force); a given value is at most
            the peak cut-off.
        softening_displacement: u_r [m], the plastic slip across a shear band over which the
            strength falls linearly from peak to residual (``hybrid.constitutive.softening``:
            the law, and its regularisation by element size). Required with ``residual``;
            ring-shear tests on clays need slips of the order of 0.1 to 0.5 m to reach
            residual (Skempton 1985), dense sands a few millimetres.
        bond: strength of the bonds between discrete elements of this material (``Bond``).
        contact: contact stiffness, friction and damping of its discrete elements
            (``Contact``).
    """

    name: str
    E: float
    nu: float
    unit_weight: float = GIVEN_OR_DERIVED
    density: float = GIVEN_OR_DERIVED
    cohesion: float = 0.0
    phi: float = 0.0
    psi: float = 0.0
    tensile_strength: float | None = None
    plastic: bool | None = None
    residual: Strength | None = None
    softening_displacement: float | None = None
    bond: Bond = Bond()
    contact: Contact = Contact()

    def __post_init__(self) -> None:
        owner = f"material '{self.name}'"

        def bad(param: str, value: object, rule: str) -> MaterialError:
            return _invalid(owner, param, value, rule)

        _check_numbers(owner, {"E": self.E, "nu": self.nu, "unit_weight": self.unit_weight,
                               "density": self.density, "cohesion": self.cohesion,
                               "phi": self.phi, "psi": self.psi,
                               "tensile_strength": self.tensile_strength})
        if self.plastic is not None and not isinstance(self.plastic, bool):
            raise bad("plastic", self.plastic, "True, False or None")
        if not isinstance(self.bond, Bond):
            raise bad("bond", self.bond, "a Bond(...)")
        if not isinstance(self.contact, Contact):
            raise bad("contact", self.contact, "a Contact(...)")
        self._resolve_weight(bad)
        if self.E <= 0:
            raise bad("E", self.E, "> 0 kPa")
        if not 0 <= self.nu < 0.5:
            raise bad("nu", self.nu, "in [0, 0.5) (0.5 is incompressible: use 0.49 at most)")
        if self.cohesion < 0:
            raise bad("cohesion", self.cohesion, ">= 0 kPa")
        if not 0 <= self.phi < 90:
            raise bad("phi", self.phi, "in [0, 90) degrees")
        if not 0 <= self.psi <= self.phi:
            raise bad("psi", self.psi, f"in [0, phi = {self.phi}] degrees (dilation <= friction)")
        if self.is_plastic and self.cohesion == 0 and self.phi == 0:
            raise bad("cohesion", self.cohesion, "> 0 or phi > 0 for a plastic material")
        if self.tensile_strength is not None and self.tensile_strength < 0:
            raise bad("tensile_strength", self.tensile_strength, ">= 0 kPa")
        if self.E < 100.0:
            warnings.warn(f"{owner}: E = {self.E:g} kPa is very soft; E is in kPa (for "
                          f"{self.E:g} MPa give E = {1000 * self.E:g})", MaterialWarning,
                          stacklevel=3)
        for key in ("phi", "psi"):
            _warn_radians(owner, key, getattr(self, key))
        self._check_softening(owner, bad)

    def _check_softening(self, owner: str, bad) -> None:
        """The residual strength lies below the peak; u_r > 0 is given with it."""
        r, u_r = self.residual, self.softening_displacement
        if r is None:
            if u_r is not None:
                raise bad("softening_displacement", u_r, "given together with residual="
                          "Strength(...) (no residual strength: no softening)")
            return
        if not isinstance(r, Strength):
            raise bad("residual", r, "a Strength(cohesion=..., phi=..., psi=...)")
        if not self.is_plastic:
            raise bad("residual", r, "None for an elastic material (give its peak strength)")
        where = f"{owner} residual"
        _check_numbers(where, {"cohesion": r.cohesion, "phi": r.phi, "psi": r.psi,
                               "tensile_strength": r.tensile_strength})
        if not 0 <= r.cohesion <= self.cohesion:
            raise _invalid(where, "cohesion", r.cohesion, f"in [0, peak {self.cohesion}] kPa")
        if not 0 <= r.phi <= self.phi:
            raise _invalid(where, "phi", r.phi, f"in [0, peak {self.phi}] degrees")
        if not 0 <= r.psi <= min(r.phi, self.psi):
            raise _invalid(where, "psi", r.psi, f"in [0, min(residual phi = {r.phi}, peak psi "
                           f"= {self.psi})] degrees")
        if r.cohesion == 0 and r.phi == 0:
            raise _invalid(where, "cohesion", r.cohesion, "> 0 or phi > 0 (some strength)")
        if r.tensile_strength is not None:
            peak_cutoff = self.peak.cutoff
            if peak_cutoff is None:
                raise _invalid(owner, "tensile_strength", None, "given (the peak's tension "
                               "cut-off) when the residual has one and phi = 0")
            if not 0 <= r.tensile_strength <= peak_cutoff:
                raise _invalid(where, "tensile_strength", r.tensile_strength,
                               f"in [0, peak cut-off {peak_cutoff:g}] kPa (softening never "
                               "raises it)")
        for key in ("phi", "psi"):
            _warn_radians(where, key, getattr(r, key))
        if u_r is None:
            raise bad("softening_displacement", u_r, "> 0 m with a residual strength (the "
                      "slip across a shear band from peak to residual)")
        _check_numbers(owner, {"softening_displacement": u_r})
        if not (math.isfinite(u_r) and u_r > 0):
            raise bad("softening_displacement", u_r, "a finite value > 0 m")

    def _resolve_weight(self, bad) -> None:
        """Fill in whichever of unit_weight and density was not given (gamma = rho g)."""
        gamma, rho = self.unit_weight, self.density
        if gamma is not None and gamma < 0:
            raise bad("unit_weight", gamma, ">= 0 kN/m3")
        if rho is not None and rho < 0:
            raise bad("density", rho, ">= 0 t/m3")
        if gamma is not None and rho is not None:
            if not math.isclose(gamma, rho * GRAVITY, rel_tol=1e-12, abs_tol=1e-300):
                raise bad("density", rho, f"unit_weight / g = {gamma / GRAVITY:g} t/m3, or "
                          "give only one of unit_weight and density")
            return
        if rho is None:
            gamma = 0.0 if gamma is None else gamma
            object.__setattr__(self, "unit_weight", gamma)
            object.__setattr__(self, "density", gamma / GRAVITY)
        else:
            object.__setattr__(self, "unit_weight", rho * GRAVITY)

    # --- derived quantities -------------------------------------------------------------
    @property
    def is_plastic(self) -> bool:
        """True when the Mohr-Coulomb return is applied."""
        if self.plastic is not None:
            return self.plastic
        return self.cohesion > 0 or self.phi > 0

    @property
    def peak(self) -> Strength:
        """The peak strength as a ``Strength`` record."""
        return Strength(cohesion=self.cohesion, phi=self.phi, psi=self.psi,
                        tensile_strength=self.tensile_strength)

    @property
    def softens(self) -> bool:
        """True when strain softening leads to a residual strength below the peak.

        That is, a residual c, phi, dilation or tension cut-off lower than the peak's.
        """
        r, p = self.residual, self.peak
        if r is None:
            return False
        return (r.cohesion < p.cohesion or r.phi < p.phi or r.psi < p.psi
                or (r.tensile_strength is not None
                    and (p.tensile_strength is None or r.tensile_strength < p.tensile_strength)))

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
        """Lame's first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) [kPa]."""
        return self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))

    @property
    def k0(self) -> float:
        """Elastic at-rest earth-pressure coefficient nu / (1 - nu) (oedometric loading)."""
        return self.nu / (1.0 - self.nu)

    @property
    def p_wave_speed(self) -> float:
        """P-wave speed sqrt((K + 4G/3) / rho) [m/s]; inf for a weightless material."""
        if not self.density:
            return math.inf
        return math.sqrt((self.bulk_modulus + 4.0 * self.shear_modulus / 3.0) / self.density)

    def weakened(self, factor: float) -> Material:
        """Every strength divided by ``factor`` (strength reduction, Zienkiewicz et al. 1975).

        c / F, tan(phi) / F, tan(psi) / F, tensile strength / F, and the same for the bond and
        contact strengths that are given (those left None follow c and phi). ``factor`` < 1
        makes the material stronger.
        """
        if not (isinstance(factor, int | float) and math.isfinite(factor) and factor > 0):
            raise MaterialError(f"material '{self.name}': strength factor {factor!r} must be a "
                                "finite number > 0")
        peak = _weakened_strength(self.peak, factor)
        with warnings.catch_warnings():  # reduced angles are degrees, whatever their size
            warnings.simplefilter("ignore", MaterialWarning)
            bond = Bond(cohesion=_divided(self.bond.cohesion, factor),
                        phi=_reduced_optional(self.bond.phi, factor),
                        tensile_strength=_divided(self.bond.tensile_strength, factor))
            contact = replace(self.contact, phi=_reduced_optional(self.contact.phi, factor),
                              cohesion=_divided(self.contact.cohesion, factor))
            return replace(self, cohesion=peak.cohesion, phi=peak.phi, psi=peak.psi,
                           plastic=self.is_plastic, tensile_strength=peak.tensile_strength,
                           residual=(None if self.residual is None else _weakened_strength(
                               self.residual, factor, peak.cutoff)),
                           bond=bond, contact=contact)
