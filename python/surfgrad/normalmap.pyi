# Type stubs of surfgrad.normalmap (python/src/bind_normalmap.cpp): the
# height-field-correct normal-map operations of Loviscach 2008 on numpy
# grids (normalmap/include/surfgrad/normalmap/operations.h has the contracts).
#
# Grids are (H, W[, C]) float32, C-contiguous, row 0 the BOTTOM row; texel
# (i, j) sits at (u, v) = (i + 0.5, j + 0.5) texels. Slopes (H, W, 2) are
# d = (dh/du, dh/dv) of a height h in texels (dimensionless, +v up, whatever
# the file's green convention); heights (H, W) are in texels; normals
# (H, W, 3) are unit tangent-space vectors, n = normalize(-d.x, -d.y, 1).
# wrap: "repeat" (one period of a tiling texture) or "clamp" (a finite
# patch). Operations on several grids need one size (ValueError otherwise).
from os import PathLike
from typing import Callable, Sequence

import numpy as np
import numpy.typing as npt

F32 = npt.NDArray[np.float32]
StrPath = str | PathLike[str]
Progress = Callable[[float], None] | None

def read_image(path: StrPath) -> tuple[F32, str]:
    """(H, W, C) raw channel values (integers as [0, 1]) and the file's sample
    type ("8", "16", "half", "float"). Row 0 is the bottom row."""
def write_image(path: StrPath, image: F32, bits: str | None = None,
                attributes: dict[str, str] | None = None) -> None:
    """Atomic write of (H, W[, C]); bits "8", "16", "half", "float" (None:
    the format's default)."""

def decode_slopes(image: F32, encoding: str = "rgb", green: str = "gl",
                  deriv_range: float = 8.0, is_float: bool = False) -> F32: ...
def decode_normals(image: F32, encoding: str = "rgb", green: str = "gl",
                   deriv_range: float = 8.0, is_float: bool = False) -> F32: ...
def encode_slopes(slopes: F32, encoding: str = "rgb", green: str = "gl",
                  deriv_range: float = 8.0, is_float: bool = False) -> F32: ...
def encode_normals(normals: F32, encoding: str = "rgb", green: str = "gl",
                   deriv_range: float = 8.0, is_float: bool = False) -> F32: ...
def normals_from_slopes(slopes: F32) -> F32: ...
def slopes_from_normals(normals: F32) -> F32: ...

def from_height(height: F32, scale: float = 1.0, wrap: str = "repeat") -> F32:
    """Central-difference slopes of scale * height."""
def to_height(slopes: F32, wrap: str = "repeat", progress: Progress = None) -> F32:
    """Least-squares (Poisson) height of the slopes, min = 0."""
def scale(slopes: F32, alpha: float) -> F32: ...
def add(a: F32, wa: float, b: F32, wb: float) -> F32: ...
def blend(a: F32, b: F32, mask: F32, wrap: str = "repeat", height_a: F32 | None = None,
          height_b: F32 | None = None) -> F32:
    """Slopes of (1 - m) hA + m hB (heights integrated when not given)."""
def modulate(slopes: F32, gain: F32, wrap: str = "repeat", height: F32 | None = None) -> F32: ...
def curves(slopes: F32, points: Sequence[tuple[float, float]] | str | None = None,
           boost: tuple[float, float] | None = None, height: F32 | None = None) -> F32:
    """A height curve through points (monotone cubic) or the paper's boost
    (P, H)."""
def deform(slopes: F32, warp: str, wrap: str = "repeat") -> F32:
    """warp "sine:A,B" or "rotate:DEG"."""

def mips(slopes: F32, layout: str = "lean", progress: Progress = None) -> list[F32]:
    """The MIP chain of a layout: "lean" (dx, dy, dxx, dyy, dxy), "toksvig"
    (nx, ny, nz, s2) or "naive" (nx, ny, nz), level 0 first."""
def write_mips(path: StrPath, levels: Sequence[F32], layout: str = "lean",
               wrap: str = "repeat") -> None: ...
def read_mips(path: StrPath) -> tuple[list[F32], list[str], str]:
    """(levels, channel names, layout): layout "lean", "toksvig", "naive", or
    the file's surfgrad:layout attribute as stored (empty for a plain EXR,
    then one level per MIP level, channels in file order)."""
def shade(normals: F32, light: tuple[float, float, float] = (0.4, 0.5, 0.77)) -> F32: ...

def rasterize_frames(mesh: object, uv_set: int, width: int, height: int,
                     dilate_texels: int = 2) -> dict[str, npt.NDArray]:
    """Per-texel normal (H, W, 3), tangent (H, W, 4) and covered (H, W) uint8
    of a RenderMesh's UV layout."""
def object_from_tangent(slopes: F32, frames: dict[str, npt.NDArray]) -> F32: ...
def tangent_from_object(normals: F32, frames: dict[str, npt.NDArray]) -> F32: ...
