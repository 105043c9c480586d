"""hybrid: continuum (dolfinx) to discontinuum (numba) geomechanics.

Units throughout: m, kN, kPa, s, t/m3 (mass density), kN/m3 (unit weight).
Sign convention: tension positive, compression negative (stresses and strains).
"""

import hashlib as _hashlib
import os as _os


def _source_stamp(root: str) -> str:
    """A short hash of the Python sources under ``root``: the numba cache's subfolder.

    Numba's cache checks only the source file of a jitted function itself: a kernel that
    inlines or calls a function of another file that has changed since it was cached would
    be loaded stale (old code beside new). One cache folder per version of the sources makes
    every change of the package compile afresh.
    """
    digest = _hashlib.sha1()
    for dirpath, dirnames, filenames in _os.walk(root):
        dirnames.sort()
        for name in sorted(filenames):
            if name.endswith(".py"):
                path = _os.path.join(dirpath, name)
                digest.update(_os.path.relpath(path, root).encode())
                with open(path, "rb") as source:
                    digest.update(source.read())
    return "src-" + digest.hexdigest()[:16]


# Threading defaults, set before numba is imported anywhere (see docs/performance.md):
# the OpenMP layer busy-waits and collapses when the cores are shared.
_os.environ.setdefault("OMP_WAIT_POLICY", "passive")
# numba's cache (NUMBA_CACHE_DIR, default ~/.cache/hybrid-numba), in a subfolder per version
# of the sources (_source_stamp); a child process inherits the subfolder as it is
_stamp = _source_stamp(_os.path.dirname(_os.path.abspath(__file__)))
_cache = (_os.environ.get("NUMBA_CACHE_DIR")
          or _os.path.join(_os.path.expanduser("~"), ".cache", "hybrid-numba"))
if _os.path.basename(_os.path.normpath(_cache)) != _stamp:
    _os.environ["NUMBA_CACHE_DIR"] = _os.path.join(_cache, _stamp)

__version__ = "0.1.0"
