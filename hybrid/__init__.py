"""hybrid: continuum (dolfinx) to discontinuum (numba) geomechanics.

Units throughout: m, kN, kPa, s, t/m3 (mass density), kN/m3 (unit weight).
Sign convention: tension positive, compression negative (stresses and strains).
"""

import os as _os

# Threading defaults, set before numba is imported anywhere (see docs/performance.md):
# the OpenMP layer busy-waits and collapses when the cores are shared.
_os.environ.setdefault("OMP_WAIT_POLICY", "passive")
_os.environ.setdefault(
    "NUMBA_CACHE_DIR",
    _os.path.join(_os.path.expanduser("~"), ".cache", "hybrid-numba"),
)

__version__ = "0.1.0"
