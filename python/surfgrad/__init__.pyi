# Type stubs of the surfgrad Python module (python/src/*.cpp): meshes,
# tangents, subdivision, blendshapes, rendering and the shared shader
# functions. Normal-map images: surfgrad.normalmap; feature curves:
# surfgrad.features. docs/python.md is the guide.
#
# Conventions (the C++ headers' contracts, carried over):
#  - arrays in: float32 (indices uint32), C-contiguous, of the documented
#    shape. Such arrays are read in place (no copy); anything else raises
#    TypeError (dtype) or ValueError (shape, contiguity, values) naming the
#    argument, its shape and dtype. Arrays out are new numpy arrays that own
#    their memory (the C++ result moved, not copied), or views of a mesh
#    that keep the mesh alive.
#  - positions and normals in object space, right-handed, units of the
#    source; triangles counter-clockwise seen from the front;
#  - texture coordinates (s, t): (0, 0) is the LOWER-left corner of the
#    image, t up (OpenGL, OBJ); glTF's v is flipped on load (t = 1 - v);
#  - tangents (V, 4): xyz unit along +s, w = +-1 with
#    bitangent = w * cross(normal, tangent) (MikkTSpace, glTF TANGENT);
#  - images and grids: (H, W[, C]) with row 0 the BOTTOM row (OpenGL);
#    np.flipud gives the usual top-first order of image libraries;
#  - threads: 0 = all cores, 1 = the calling thread, 2..1024 that many;
#    the results are the same bits for every count. Long calls release the
#    GIL;
#  - untrusted input (files, text) that is malformed raises InputError
#    naming the file, the element and the reason.
from os import PathLike
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import numpy.typing as npt

from . import features as features
from . import normalmap as normalmap

__version__: str

F32 = npt.NDArray[np.float32]
U32 = npt.NDArray[np.uint32]
U8 = npt.NDArray[np.uint8]
StrPath = str | PathLike[str]
Progress = Callable[[float], None] | None

class InputError(ValueError):
    """Malformed untrusted input: str(e) is "<file>: <element>: <reason>"."""
    file: str
    element: str
    reason: str

# ---------------------------------------------------------------------------
# Meshes

class MorphTarget:
    """A blendshape of a RenderMesh: per-vertex deltas, object space."""
    name: str
    position_deltas: F32  # (V, 3) or (0, 3)
    normal_deltas: F32    # (V, 3) or (0, 3)
    tangent_deltas: F32   # (V, 3) or (0, 3)

class RenderMesh:
    """Indexed triangle mesh with split vertices (glTF's model): every
    per-vertex array has vertex_count rows. Array attributes are views into
    the mesh (writes go through; the view keeps the mesh alive); assigning
    an array copies it after checking dtype and shape."""
    def __init__(self, positions: F32, indices: U32, normals: F32 | None = None,
                 uv_sets: Sequence[F32] = (), tangents: F32 | None = None,
                 tangent_uv_set: int = -1, name: str = "") -> None: ...
    name: str
    positions: F32            # (V, 3)
    normals: F32              # (V, 3) or (0, 3): unit
    indices: U32              # (T, 3), counter-clockwise
    tangents: F32             # (V, 4) or (0, 4)
    tangent_uv_set: int       # the UV set the tangents belong to, -1: none
    uv_sets: list[F32]        # each (V, 2); the list is new, its arrays are views
    @property
    def morph_targets(self) -> list[MorphTarget]: ...
    @property
    def morph_weights(self) -> F32:
        """(K,) default weights (a copy)."""
    @property
    def vertex_count(self) -> int: ...
    @property
    def triangle_count(self) -> int: ...
    def set_uv_set(self, index: int, uvs: F32) -> None:
        """Replaces UV set `index` (index == len(uv_sets) appends one)."""
    def copy(self) -> RenderMesh: ...

class PolygonMesh:
    """A control cage: polygons with face-varying UV sets and OpenSubdiv
    tags (what the loaders read and the subdivider refines). positions,
    face_sizes and face_vertices are views (the topology ones read-only);
    the rest are copies. The constructor validates like a loader
    (InputError naming the face, vertex or tag)."""
    def __init__(self, positions: F32, face_sizes: U32, face_vertices: U32,
                 uv_sets: Sequence[tuple[str, F32, U32]] = (), scheme: str = "catmark",
                 creases: Sequence[tuple[int, int, float]] = (),
                 corners: Sequence[tuple[int, float]] = (), holes: Sequence[int] = (),
                 name: str = "") -> None: ...
    name: str
    positions: F32            # (V, 3) view, assignable in place
    @property
    def face_sizes(self) -> U32:
        """(F,) corners per face (>= 3); a read-only view."""
    @property
    def face_vertices(self) -> U32:
        """(C,) = sum(face_sizes) vertex indices, CCW; a read-only view."""
    @property
    def normals(self) -> F32:
        """(N, 3) face-varying normal values, or (0, 3) (a copy)."""
    @property
    def normal_indices(self) -> U32:
        """(C,) or (0,) (a copy)."""
    @property
    def scheme(self) -> str:
        """"catmark" | "loop" | "bilinear"."""
    @property
    def creases(self) -> list[tuple[int, int, float]]:
        """(v0, v1, sharpness) per tagged edge; sharpness >= 10 is infinite."""
    @property
    def corners(self) -> list[tuple[int, float]]:
        """(vertex, sharpness) per corner tag."""
    @property
    def holes(self) -> list[int]:
        """Face indices tagged as holes (sorted)."""
    @property
    def morph_weights(self) -> F32: ...
    @property
    def uv_sets(self) -> list[tuple[str, F32, U32]]:
        """(name, values (K, 2), indices (C,)) per UV set (copies)."""
    @property
    def morph_targets(self) -> list[tuple[str, F32]]:
        """(name, position deltas (V, 3)) per target (copies)."""
    @property
    def vertex_count(self) -> int: ...
    @property
    def face_count(self) -> int: ...
    @property
    def corner_count(self) -> int: ...
    def copy(self) -> PolygonMesh: ...

def load_mesh(path: StrPath, *, repair: bool = False, threads: int = 0,
              allow_outside_folder: bool = False) -> RenderMesh:
    """Any of .obj .off .ply .stl .gltf .glb as a triangle mesh (polygons
    fanned, vertices split at UV/normal seams; glTF primitives merged in
    world space). Raises InputError for a malformed or invalid file."""

def load_cage(path: StrPath, *, repair: bool = False, threads: int = 0,
              allow_outside_folder: bool = False) -> PolygonMesh:
    """Any supported file as a validated control cage."""

def load_report(path: StrPath, *, repair: bool = False) -> dict[str, Any]:
    """What loading `path` as a cage noted and repaired: notes (list of str),
    degenerate_faces_dropped, duplicate_vertices_welded, isolated_vertices."""

def save_mesh(path: StrPath, mesh: RenderMesh | PolygonMesh, *,
              write_morph_targets: bool = True) -> list[str]:
    """Writes .gltf .glb .obj .ply atomically; returns one note per kind of
    data the format cannot hold."""

def validate(cage: PolygonMesh, *, name: str = "mesh") -> dict[str, Any]:
    """Checks a cage; raises InputError naming the first problem. Returns
    the report (see load_report)."""

def repaired(cage: PolygonMesh, *, name: str = "mesh") -> tuple[PolygonMesh, dict[str, Any]]:
    """A repaired copy (bitwise-equal vertices welded, degenerate faces
    dropped) and the report; InputError for what repair cannot fix."""

def describe(cage: PolygonMesh) -> dict[str, Any]:
    """Topology summary: vertices, faces, edges, boundary_edges,
    boundary_loops, non_manifold_edges, manifold, euler_characteristic, ..."""

def weld(mesh: RenderMesh, *, threads: int = 0) -> tuple[RenderMesh, int]:
    """(welded copy, vertices removed): vertices whose every attribute is
    bitwise equal become one. Operations that change the vertex count
    return a new mesh (views of the old one stay valid)."""

def to_render_mesh(cage: PolygonMesh) -> RenderMesh: ...
def to_polygon_mesh(mesh: RenderMesh) -> PolygonMesh: ...

# ---------------------------------------------------------------------------
# Tangents

def mikktspace(positions: F32, normals: F32, uvs: F32, corner_vertices: U32,
               face_sizes: U32 | None = None, *, threads: int = 0,
               frames: bool = False) -> F32 | dict[str, F32]:
    """MikkTSpace tangents per face corner, bit-identical to the reference
    mikktspace.c. positions/normals (V, 3), uvs (V, 2), corner_vertices
    (C,) or (T, 3); face_sizes (F,) (None: triangles): faces of other than
    3 or 4 corners are ignored as by the reference (their corners get
    (0, 0, 0, 0); triangulate first). Values: finite, |positions|, |uvs|
    <= 2^60, |normal components| <= 16 (ValueError naming the array).
    Returns
    (C, 4) = (tangent, sign); frames=True returns a dict with tangent (C, 3),
    mag_s (C,), bitangent (C, 3), mag_t (C,), sign (C,)."""

def generate_tangents(mesh: RenderMesh, method: str = "mikktspace", uv_set: int = 0,
                      frame: LimitFrame | None = None, *,
                      threads: int = 0) -> tuple[RenderMesh, int]:
    """(copy of `mesh` with tangents, count): "mikktspace" splits vertices
    whose corners disagree (count = vertices added); "limit" needs the
    Subdivider's limit frame (count = irregular vertices); "pixel" clears
    them (the shader builds the frame)."""

def limit_tangents(dpdu: F32, dpdv: F32, dstdu: F32, dstdv: F32) -> tuple[F32, U8]:
    """The limit-surface tangent per point from first derivatives: (N, 4)
    tangents and (N,) cases (0 regular, 1 degenerate UV, 2 degenerate
    surface)."""

def uv_area_within_rounding(mesh: RenderMesh, uv_set: int = 0) -> int: ...

class MikkTSpaceGenerator:
    """Keeps scratch buffers between calls (many meshes or frames)."""
    def __init__(self, threads: int = 0) -> None: ...
    def generate(self, positions: F32, normals: F32, uvs: F32, corner_vertices: U32,
                 face_sizes: U32 | None = None, out: F32 | None = None) -> F32:
        """As mikktspace(); `out` (C, 4) float32 is filled in place."""
    def last_step_times(self) -> list[tuple[str, float]]:
        """(step, milliseconds) of the last generate()."""
    def last_generate_ms(self) -> float:
        """Wall milliseconds of the C++ generate() inside the last
        generate() (the binding's checks and conversions excluded)."""

# ---------------------------------------------------------------------------
# Subdivision

class LimitFrame:
    """Limit-surface derivatives aligned with a render mesh's vertices, each
    w.r.t. the vertex's ptex (u, v) (copies)."""
    dpdu: F32                # (V, 3)
    dpdv: F32                # (V, 3)
    duvdu: list[F32]         # per UV set (V, 2)
    duvdv: list[F32]
    ptex_face: U32           # (V,)
    ptex_uv: F32             # (V, 2)

class Subdivider:
    """OpenSubdiv refinement of a cage to `level` (uniform), optionally on
    the limit surface, optionally with stencils for animated cages."""
    def __init__(self, cage: PolygonMesh, level: int = 2, *, limit: bool = False,
                 animate: bool = False, scheme: str | None = None,
                 boundary: str | None = None, fvar: str | None = None,
                 threads: int = 0, memory_budget: int = 0) -> None: ...
    @property
    def refined(self) -> PolygonMesh: ...
    @property
    def render_mesh(self) -> RenderMesh: ...
    @property
    def limit_frame(self) -> LimitFrame | None: ...
    @property
    def render_to_refined_vertex(self) -> U32: ...
    def update(self, cage_positions: F32, *, out: RenderMesh | None = None,
               normals: bool = True,
               frame: bool = False) -> RenderMesh | tuple[RenderMesh, LimitFrame]:
        """Positions and normals of render_mesh for new (V, 3) cage
        positions through the stencil tables (animate=True). `out` (a copy
        of render_mesh) is written in place and returned; else a new mesh.
        frame=True (limit=True) returns (mesh, LimitFrame) with the moved
        surface's dpdu and dpdv."""
    @property
    def timings(self) -> dict[str, float]: ...
    @property
    def used_specialized_refiner(self) -> bool: ...
    @property
    def stencil_weight_count(self) -> int: ...

def estimate_subdivision_cost(cage: PolygonMesh, level: int, *,
                              limit: bool = False) -> dict[str, int]:
    """Level-N counts and the peak heap bytes of a build, from the cage
    alone: faces, vertices, edges, corners, fvar_values, render_vertices,
    bytes."""

# ---------------------------------------------------------------------------
# Blendshapes

def morph_cage_positions(cage: PolygonMesh, weights: F32) -> F32: ...

class Morpher:
    def __init__(self, mesh: RenderMesh, frame: LimitFrame | None = None) -> None: ...
    def apply(self, weights: F32, normals: str = "recompute") -> RenderMesh:
        """P = P0 + sum w_i dP_i; normals "recompute" or "blend" (glTF)."""

# ---------------------------------------------------------------------------
# Baking (docs/bake.md)

def bake(high: RenderMesh, cage: PolygonMesh, *, size: int | tuple[int, int] = 1024,
         uv_set: int = 0, surface: str = "limit", level: int = 2, isolation: int = 4,
         max_distance: float = 0.0, pad: int = 8, residual: bool = False,
         threads: int = 0, memory_budget: int = 0) -> dict[str, Any]:
    """`high` baked onto the limit surface of `cage` (surface="refined": the cage
    refined to `level`, MikkTSpace frames) in UV set `uv_set`'s layout.
    Returns (H, W[, C]) arrays, row 0 at the bottom: state (uint8: 0 empty,
    1 hit, 2 miss, 3 padding), displacement, object_normal, tangent_slopes,
    residual_slopes (with residual=True), position, normal, tangent; and stats
    (dict of counts and seconds)."""

# ---------------------------------------------------------------------------
# Rendering and the shared functions

def render(scene: Mapping[str, Any] | str | PathLike[str] | None = None, *,
           width: int = 0, height: int = 0, aov: str = "color", renderer: str = "cpu",
           seconds: float = 0.0, progress: Progress = None) -> F32:
    """Renders a scene (a dict in the scene-file schema, its JSON text
    (a str starting with '{'), a path to a .json scene or a model file, or
    None for the built-in scene) to (H, W, 4) float32 RGBA,
    row 0 at the bottom. renderer "cpu" (the reference) or "gl" (OpenGL 4.5
    through EGL). aov: color, normal, surfgrad, tangent, bitangent,
    basenormal, uv, primid, patch."""

def eval_functions() -> list[str]: ...
def eval_signature(name: str) -> dict[str, Any]:
    """name, summary, inputs and outputs: lists of dicts with key, width,
    kind ("float", "bool", "int"), optional, default, doc."""
def eval(name: str, **inputs: npt.ArrayLike) -> dict[str, F32]:
    """Runs a shared shader function (the C++ build) over arrays: each input
    (..., width) (width-1 inputs: (..., 1) or (...)), the record axes
    broadcast against the other inputs'; omitted optional inputs take their
    defaults. Returns each output as (..., width) ((...) for width 1).
    Values finite with |x| <= 1e18; bool inputs 0 or 1, int inputs
    integers in their range."""
