"""hullskin: fit one fair NURBS surface to a ship's offsets, from Python.

A thin layer over the Rust library that the ``hullskin`` command line calls, with the same
defaults, so the figures equal the command line's on the same input::

    import hullskin
    f = hullskin.fit()                 # the built-in Series 60 Cb 0.60 parent
    print(f.error["overall"])          # true closest-point error, in the offsets' units
    s = f.surface
    s.evaluate([0.1, 0.5], [0.2, 0.7]) # points, shape (2, 3)
    s.hydrostatics(draft=6.5)          # as `hullskin hydrostatics --draft 6.5 --format json`

Long fits release the GIL and stop on Ctrl-C (KeyboardInterrupt). Bad arguments raise
ValueError or TypeError; library errors raise ``HullskinError`` (a ValueError) with the
library's message, and ``file``, ``line``, ``column`` where the error has a place.

Design studies over many hulls on a Dask cluster: :mod:`hullskin.study`.
"""

from ._hullskin import (
    DEFAULT_HELD_OUT_FOLDS,
    SEA_WATER_DENSITY,
    Fit,
    HullskinError,
    Offsets,
    Surface,
    __version__,
    fit,
    read_offsets,
)
from . import study  # noqa: E402  (design studies on Dask; imports pandas only when run)

__all__ = [
    "DEFAULT_HELD_OUT_FOLDS",
    "SEA_WATER_DENSITY",
    "Fit",
    "HullskinError",
    "Offsets",
    "Surface",
    "__version__",
    "fit",
    "read_offsets",
    "study",
]
