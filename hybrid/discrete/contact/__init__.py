"""Contact between discrete elements: grid broad phase, overlap-area narrow phase, forces.

Thesis (G. S. Bala 2008) sections 4.2-4.3 and 4.8.2, eqs 4.6, 4.9, 4.10 and appendices A-C.

Units: m, kN, kPa, s, t; forces are per unit thickness (kN/m), areas in m2 (per unit
thickness m3/m), energies in kJ/m.

Each step of the explicit loop: every few steps ``find_contact_pairs`` lists the candidate
pairs (elements whose boxes, grown by a margin, overlap) and ``carry_contact_history`` moves
the tangential history of the pairs that stay onto the new list; every step
``contact_forces`` computes, for each candidate pair, the overlap of the two elements, the
normal force ``k_n A`` (overlap area ``A``) with damping, the tangential spring capped by
friction, and adds the pair force to the nodes through the elements' shape functions at the
overlap centroid.  ``contact_energy`` and ``mid_step_work`` give the terms of the run's
energy ledger.

Modules:

* ``polygon``: overlap geometry (clipping, area, centroid, contact normal and length, the
  split of a non-convex quad at its reflex vertex, element boxes), ``overlap``;
* ``law``: the force of one pair (the law at the contact point and its distribution to the
  nodes);
* ``broad_phase``: ``find_contact_pairs``, ``carry_contact_history``;
* ``forces``: the parallel loop over the pairs, ``contact_forces`` (checked) and
  ``add_contact_forces`` (unchecked, with caller-owned ``ContactBuffers``: the hot path),
  ``rigid_contact_mass``;
* ``energy``: ``contact_energy``, ``mid_step_work``;
* ``walls``: the smooth rigid walls of the roller supports (``DiscreteState.walls``), a
  frictionless contact for every element, ``add_wall_forces``, ``wall_energy``.
"""

from hybrid.discrete.contact.broad_phase import carry_contact_history, find_contact_pairs
from hybrid.discrete.contact.energy import contact_energy, mid_step_work
from hybrid.discrete.contact.forces import contact_forces, rigid_contact_mass
from hybrid.discrete.contact.polygon import overlap

__all__ = [
    "carry_contact_history",
    "contact_energy",
    "contact_forces",
    "find_contact_pairs",
    "mid_step_work",
    "overlap",
    "rigid_contact_mass",
]
