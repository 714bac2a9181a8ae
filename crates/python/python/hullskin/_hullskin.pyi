"""Type stubs of the native module hullskin._hullskin (crates/python/src)."""

import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.float64]
PathLike = Union[str, "os.PathLike[str]"]

SEA_WATER_DENSITY: float
DEFAULT_HELD_OUT_FOLDS: int
__version__: str

class HullskinError(ValueError):
    """A library error: its message, and where the input was wrong (else None)."""

    file: Optional[str]
    line: Optional[int]
    column: Optional[int]

class Offsets:
    """A ship's offsets: sections along the length (x forward, y half-breadth, z up)."""

    @staticmethod
    def from_sections(
        sections: Sequence[ArrayLike],
        units: str = "m",
        labels: Optional[Sequence[str]] = None,
        source: str = "python",
        perpendiculars: Optional[Tuple[float, float]] = None,
    ) -> "Offsets": ...
    @property
    def sections(self) -> List[FloatArray]: ...
    @property
    def labels(self) -> List[str]: ...
    @property
    def source(self) -> str: ...
    @property
    def units(self) -> str: ...
    @property
    def perpendiculars(self) -> Optional[Tuple[float, float]]: ...
    @property
    def notes(self) -> List[str]: ...
    @property
    def warnings(self) -> List[str]: ...
    def scaled(self, x: float = 1.0, y: float = 1.0, z: float = 1.0) -> "Offsets": ...
    def __len__(self) -> int: ...

class Surface:
    """A NURBS surface in `units`; parameters outside the domain are clamped."""

    def __init__(
        self,
        degree: Tuple[int, int],
        knots_u: ArrayLike,
        knots_v: ArrayLike,
        control_points: ArrayLike,
        weights: Optional[ArrayLike] = None,
        units: str = "m",
        source: str = "python",
    ) -> None: ...
    @property
    def degree(self) -> Tuple[int, int]: ...
    @property
    def knots_u(self) -> FloatArray: ...
    @property
    def knots_v(self) -> FloatArray: ...
    @property
    def control_points(self) -> FloatArray:
        """Shape (nu, nv, 3)."""
    @property
    def weights(self) -> FloatArray:
        """Shape (nu, nv)."""
    @property
    def units(self) -> str: ...
    @property
    def source(self) -> str: ...
    @property
    def domain(self) -> Tuple[Tuple[float, float], Tuple[float, float]]: ...
    def evaluate(self, u: ArrayLike, v: ArrayLike) -> FloatArray:
        """Points, shape of u (or v) + (3,)."""
    def derivatives(self, u: ArrayLike, v: ArrayLike) -> Dict[str, FloatArray]:
        """Keys point, su, sv, suu, suv, svv."""
    def normal(self, u: ArrayLike, v: ArrayLike) -> FloatArray: ...
    def curvature(self, u: ArrayLike, v: ArrayLike) -> Dict[str, FloatArray]:
        """Keys gaussian, mean, k1, k2."""
    def closest_points(self, points: ArrayLike) -> Dict[str, FloatArray]:
        """Keys u, v, points, distance, converged."""
    def hydrostatics(
        self,
        draft: float,
        to: Optional[float] = None,
        step: Optional[float] = None,
        density: float = ...,
        lpp: Optional[float] = None,
        ap: Optional[float] = None,
    ) -> Dict[str, Any]:
        """As `hullskin hydrostatics --format json`: source, units, density, rows."""
    def tessellate(
        self, tolerance: Optional[float] = None, mirror: bool = False
    ) -> Tuple[FloatArray, npt.NDArray[np.int64]]: ...
    def write_iges(self, path: PathLike, mirror: bool = False, timestamp: Optional[int] = None) -> None: ...
    def write_step(self, path: PathLike, mirror: bool = False, timestamp: Optional[int] = None) -> None: ...
    def write_stl(
        self, path: PathLike, tolerance: Optional[float] = None, mirror: bool = False, ascii: bool = False
    ) -> None: ...
    def to_json(self) -> str: ...
    @staticmethod
    def from_json(text: str, source: str = "surface.json") -> "Surface": ...

class Fit:
    """A fitted surface with report.json's figures."""

    @property
    def surface(self) -> Surface: ...
    @property
    def offsets(self) -> Offsets: ...
    @property
    def report(self) -> Dict[str, Any]: ...
    @property
    def error(self) -> Dict[str, Any]: ...
    @property
    def validity(self) -> List[Dict[str, Any]]: ...
    @property
    def timings(self) -> Dict[str, float]: ...
    @property
    def method(self) -> str: ...
    @property
    def warnings(self) -> List[str]: ...
    def to_json(self) -> str: ...

def read_offsets(
    path: Optional[PathLike] = None,
    units: str = "m",
    lpp: Optional[float] = None,
    beam: Optional[float] = None,
    design_draft: Optional[float] = None,
    outliers: str = "warn",
    degree_u: int = 3,
) -> Offsets: ...
def fit(
    offsets_or_path: Union[Offsets, PathLike, None] = None,
    *,
    method: str = "approx",
    ctrl: Optional[Tuple[int, int]] = None,
    tolerance: Union[float, str, None] = None,
    seed: int = 1,
    iterations: Optional[int] = None,
    population: Optional[int] = None,
    degree: Tuple[int, int] = (3, 3),
    param: str = "centripetal,chord",
    fair: Union[str, float, None] = None,
    knuckles: str = "auto",
    corner_angle: float = 30.0,
    envelope: str = "hold",
    weights: str = "full",
    control_points: str = "resolved",
    param_correction: bool = False,
    fitted_params: bool = False,
    held_out: int = 4,
    units: str = "m",
    lpp: Optional[float] = None,
    beam: Optional[float] = None,
    design_draft: Optional[float] = None,
    outliers: str = "warn",
) -> Fit:
    """Fit one NURBS surface, as `hullskin fit` does with the same arguments (fair None = "auto")."""
