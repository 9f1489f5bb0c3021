# Type stubs of surfgrad.features (python/src/bind_features.cpp): feature
# curves (SVG, fonts, JSON networks) baked into feature maps that give the
# exact distance to the curves at any magnification (Parilov-Rosenberg-Zorin
# 2005, Parilov-Zorin 2008), and sampling them as the shader does
# (features/include/surfgrad/features/feature_maps.h has the contracts).
# Points are in texel space: (0, 0) the lower-left corner of the map,
# texel (i, j) covers [i, i + 1] x [j, j + 1], y up.
from os import PathLike
from typing import Any, Callable

import numpy as np
import numpy.typing as npt

F32 = npt.NDArray[np.float32]
StrPath = str | PathLike[str]

class FeatureMaps:
    @property
    def size(self) -> int: ...
    @property
    def mode(self) -> str: ...
    @property
    def has_near_field(self) -> bool: ...
    @property
    def stats(self) -> dict[str, Any] | None:
        """What the bake did (None for loaded maps): size,
        input_to_texel_scale, input_to_texel_offset, texels_with_features,
        texels_with_segments, segments_kept, segments_dropped,
        curved_segments, invalid_texels, optimized_texels, fallback_texels,
        near_pieces, threads, seconds."""
    def distance(self) -> F32:
        """(N + 1, N + 1) corner distances (texels, clamped to the band)."""
    def sample(self, points: F32, near: str = "exact") -> dict[str, npt.NDArray]:
        """What the shader computes at (M, 2) texel positions: dist (M,),
        grad (M, 2) unit, side (M,) +-1, profile (M,) int32 (the nearest
        curve's entry in the map's profile table in the exact near field,
        -1 elsewhere: the layer's profile), width (M,) (texels; 0: the
        layer's width)."""
    def save(self, path: StrPath) -> None: ...

def load(path: StrPath) -> FeatureMaps: ...
def bake(source: StrPath | None = None, *, svg: str | None = None, json: str | None = None,
         font: StrPath | None = None, text: str | None = None, size: int = 512,
         mode: str = "linear", margin: float = 8.0, band: float = 16.0,
         smooth_iterations: int = 10, near_field: bool = False, threads: int = 0,
         progress: Callable[[str, float], None] | None = None) -> FeatureMaps:
    """Bakes curves from a file (.svg, .json; a font with `text`) or from
    SVG/JSON text."""
def profile_names() -> list[str]: ...
