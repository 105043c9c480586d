"""The energy ledger of the discrete engine (kJ per m thickness).

The terms balance as

    E_kin + E_strain + E_contact + D_damping + D_friction + D_contact_damping
        + D_normal_defect + residual
        = E_kin(0) + E_strain(0) + E_contact(0) + W_loads + W_supports,

where E_contact is the elastic energy stored in the contacts (``contact.contact_energy``:
k_n A^2 / (2 L_c) + |F_t|^2 / (2 k_t L_c) per pair; ``contact.walls.wall_energy`` for the
smooth walls), D_contact_damping minus the work of the
contact damping forces as applied (after the no-adhesion clamp) on the mid-step velocity
(``contact.mid_step_work``: the kinetic energy of the central-difference update changes by
exactly F(t) . v_mid dt), D_friction minus the work of the tangential contact forces on the
mid-step velocity less the energy still stored in the tangential springs (in steady sliding
it is (c L_c + mu N) x slip), and the residual holds plastic dissipation and time-integration
error.
D_normal_defect is minus the work of the elastic normal contact forces on the mid-step
velocity less the stored k_n A^2 / (2 L_c): energy the overlap-area normal force absorbs
(> 0) or gives (< 0) over a contact episode, because it is not exactly conservative (corner
contacts with a varying contact length, the O(dt^2) error of stiff contacts) and U_n is
approximate (D5: +2.8 % of the work of gravity with contact damping 0.2, -1.0 % without).
W_loads, W_supports, D_damping (mass and local damping, thesis eq 3.12, and the dashpots of
transmitting boundaries) accumulate per tie group in ``DiscreteState.group_energy`` (the step
kernel, ``integrate``) and are folded into the slots ``LEDGER_GROUPS`` of
``DiscreteState.ledger`` when the groups change; the contact
works accumulate in its slots ``LEDGER_FRICTION``, ``LEDGER_CONTACT_DAMPING`` and
``LEDGER_CONTACT_NORMAL`` (the solver's ledger update after each step).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from hybrid.discrete import integrate
from hybrid.discrete.elements import strain_energy
from hybrid.discrete.state import (
    LEDGER_CONTACT_DAMPING,
    LEDGER_CONTACT_NORMAL,
    LEDGER_FRICTION,
    LEDGER_GROUPS,
    DiscreteState,
)

__all__ = ["EnergyLedger", "LEDGER_FRICTION", "LEDGER_CONTACT_DAMPING", "LEDGER_GROUPS",
           "LEDGER_CONTACT_NORMAL", "group_works", "support_work"]


def group_works(state: DiscreteState) -> np.ndarray:
    """The works the step kernel accumulates per tie group, summed over the state so far.

    [loads and gravity, supports, mass damping and dashpots, local damping] [kJ/m]
    (``integrate``), the part folded into ``LEDGER_GROUPS`` when the groups changed included.
    """
    return state.group_energy.sum(axis=0) + state.ledger[LEDGER_GROUPS]


def support_work(state: DiscreteState) -> float:
    """Work done on the state by its supports (fixed and prescribed velocities) so far [kJ/m].

    The step kernel's own account (reaction times velocity times dt), so a platen's mean
    reaction over a displacement is this work's change over it.
    """
    return float(group_works(state)[1])


@dataclass(frozen=True)
class EnergyLedger:
    """The energy terms of a discrete state at one instant [kJ/m] (see the module docstring).

    The works and dissipations are totals since the state was made (a continued run starts
    with them non-zero); compare two ledgers with :meth:`residual`.
    """

    kinetic: float  # 1/2 sum m v.v with the staggered velocity v(t - dt/2)
    strain: float  # elastic strain energy of the elements
    contact_elastic: float  # energy stored in the current contact pairs (normal + tangential)
    contact_normal_defect: float  # minus the work of the elastic normal forces less U_n
    work_loads: float  # work of gravity and the external loads
    work_supports: float  # work of the support reactions (fixed / prescribed velocities)
    damping: float  # mass-damping, local-damping and boundary-dashpot dissipation
    friction: float  # minus the work of the tangential contact forces less U_t
    contact_damping: float  # minus the work of the contact damping forces

    @classmethod
    def measure(cls, state: DiscreteState) -> EnergyLedger:
        """The ledger of ``state`` now: its energies and its accumulated works."""
        ge = group_works(state)
        u_n = u_t = 0.0
        if state.contact_pairs.shape[0]:
            from hybrid.discrete import contact as cmod

            u_n, u_t = cmod.contact_energy(state.x, state.element_nodes, state.element_material,
                                           state.contact_table, state.contact_pairs,
                                           state.contact_shear)
        if state.walls.shape[0]:  # the smooth walls' normal springs
            from hybrid.discrete.contact.walls import wall_energy

            u_n += wall_energy(state.x, state.element_nodes, state.element_material,
                               state.contact_table, state.fixed, state.walls)
        return cls(kinetic=integrate.kinetic_energy(state),
                   strain=strain_energy(state),
                   contact_elastic=u_n + u_t,
                   contact_normal_defect=float(state.ledger[LEDGER_CONTACT_NORMAL]) - u_n,
                   work_loads=float(ge[0]),
                   work_supports=float(ge[1]),
                   damping=float(ge[2] + ge[3]),
                   friction=float(state.ledger[LEDGER_FRICTION]) - u_t,
                   contact_damping=float(state.ledger[LEDGER_CONTACT_DAMPING]))

    @property
    def mechanical(self) -> float:
        """E = kinetic + strain + contact elastic energy [kJ/m]."""
        return self.kinetic + self.strain + self.contact_elastic

    def balance(self) -> float:
        """Energy held and dissipated minus the work done on the system [kJ/m].

        Its change between two instants is minus the ledger's residual over that interval.
        """
        return (self.kinetic + self.strain + self.contact_elastic + self.damping
                + self.friction + self.contact_damping + self.contact_normal_defect
                - self.work_loads - self.work_supports)

    def residual(self, start: EnergyLedger) -> float:
        """Energy missing since ``start`` [kJ/m] (> 0: plastic dissipation, integration error).

        It is ``start.balance() - self.balance()``: zero for an elastic, exactly integrated
        motion.
        """
        return start.balance() - self.balance()

    def as_dict(self) -> dict[str, float]:
        """The terms by name, in field order."""
        return {f.name: getattr(self, f.name) for f in fields(self)}
