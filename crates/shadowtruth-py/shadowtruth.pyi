"""shadowtruth: how wrong shadow maps are, against an exact ray-traced reference.

Images are numpy arrays of shape (height, width), row 0 at the top, one value per camera pixel.
Cameras and lights are named; None takes the scene's first. Tracing releases the GIL.
"""

from os import PathLike
from pathlib import Path
from typing import Literal, Optional, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str
DEFAULT_COVERAGE_GRID: int
"""Sub-pixel grid (N for N×N) of coverage_reference unless one is given: 4."""
DEFAULT_AREA_LIGHT_GRID: int
"""Light-sample grid (N for N×N) of area_light_reference unless one is given: 8."""
MAX_REFERENCE_GRID: int
"""The largest grid of either soft reference: 64."""
DEFAULT_DEPTH_TOLERANCE: float
"""Relative depth tolerance of score unless one is given: 1e-3."""
DEFAULT_ATTRIBUTION_RESOLUTION: int
"""Shadow-map resolution whose texel footprint score's attribution uses unless one is given: 2048."""
DEFAULT_SAMPLE_PIXELS: int
"""Pixels verify samples per view unless told: 100000."""

class Error(ValueError):
    """A scene, light or buffer the library refuses; the message names the file and the JSON path or pixel."""

class Scene:
    """A loaded scene with its cameras and lights; its BVH is built once, on the first call that traces."""

    @property
    def name(self) -> str:
        """The scene's name."""
    @property
    def path(self) -> Path:
        """The file the scene was read from."""
    @property
    def cameras(self) -> list[str]:
        """The cameras' names, in the file's order (the first is the default)."""
    @property
    def lights(self) -> list[str]:
        """The lights' names, in the file's order (the first is the default)."""
    @property
    def triangle_count(self) -> int:
        """Triangles of the scene, instanced ones included."""
    def image_size(self, camera: Optional[str] = None) -> Tuple[int, int]:
        """(width, height) of the camera's image; its arrays have shape (height, width)."""

def load_scene(path: Union[str, PathLike[str]]) -> Scene:
    """Loads a scene file (shadowtruth/scene/v1 JSON, or a glTF file as a scene).

    Raises shadowtruth.Error naming the file and the JSON path at fault.
    """

def hard_reference(
    scene: Scene, camera: Optional[str] = None, light: Optional[str] = None
) -> npt.NDArray[np.uint8]:
    """The exact hard shadow mask: uint8 (height, width) with the codes of `shadowtruth reference`'s PNG:
    255 lit, 0 shadowed, 128 background, 64 facing away from the light, 192 outside the light,
    96 uncertain (the reference cannot decide the pixel beyond doubt)."""

def coverage_reference(
    scene: Scene, camera: Optional[str] = None, light: Optional[str] = None, grid: int = 4
) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """(visibility, std_error), float32 (height, width): hard visibility averaged over a grid×grid
    sub-pixel grid (1 to 64), as `shadowtruth reference --kind coverage`; 0 where not evaluated."""

def area_light_reference(
    scene: Scene, camera: Optional[str] = None, light: Optional[str] = None, grid: int = 8
) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """(visibility, std_error), float32 (height, width): the fraction of grid×grid light samples
    (1 to 64) each point sees, as `shadowtruth reference --kind area`; the light needs a size.
    Raises shadowtruth.Error for a light without one."""

class Case(TypedDict):
    x: int
    y: int
    surface_triangle: int
    traced_shadowed: bool
    exact_shadowed: bool
    expected: Literal["lit", "shadowed", "either"]
    triangle: Optional[int]
    at_boundary: bool
    inconsistent: bool

class Verification(TypedDict):
    camera: str
    light: str
    width: int
    height: int
    evaluated: int
    checked: int
    checked_at_boundary: int
    agree: int
    disagree_at_boundary: int
    disagree_away_from_boundary: int
    disagree_in_band: int
    disagree_outside_band: int
    in_band: int
    inconsistent: int
    cases: list[Case]
    seconds: float

def verify(
    scene: Scene,
    camera: Optional[str] = None,
    light: Optional[str] = None,
    pixels: Union[None, int, Literal["all"]] = None,
) -> Verification:
    """Checks the hard reference against exact predicates, as `shadowtruth verify`: the view's entry of
    its --json output. pixels: "all", or about N evaluated pixels plus every boundary pixel (default 100000).
    The reference is right when disagree_outside_band and inconsistent are 0."""

class Rates(TypedDict):
    false_shadow: float
    false_lit: float
    error: float

class Score(TypedDict):
    pixels: int
    background: int
    facing_away: int
    outside_light: int
    evaluated: int
    uncertain: int
    false_shadow: int
    false_lit: int
    aliasing: int
    acne: int
    leak: int
    light_bleeding: int
    surface_mismatch: int
    rates: Rates

def score(
    scene: Scene,
    camera: Optional[str],
    light: Optional[str],
    visibility: npt.NDArray[np.float32],
    depth: Optional[npt.NDArray[np.float32]] = None,
    depth_tolerance: float = 1e-3,
    resolution: int = 2048,
) -> Score:
    """Scores a renderer's visibility buffer (float32 (height, width), 1 lit, 0 shadowed, NaN or negative
    for background) against the exact hard reference, as `shadowtruth score --visibility`: the counts of
    its report.json run (with the attribution aliasing / acne / leak / light bleeding at `resolution`) and their rates.
    depth: optional camera depth (float32, same shape) for surface mismatches. Raises ValueError for a
    wrong type, dtype, shape or value."""
