"""surfgrad: surface-gradient bump mapping on subdivision meshes.

Meshes (load_mesh, load_cage, save_mesh), MikkTSpace and limit tangents,
OpenSubdiv subdivision with limit frames and animated cages, blendshapes,
rendering and the shared shader functions (eval) on numpy arrays;
normal-map operations in surfgrad.normalmap, feature curves in
surfgrad.features. The guide is docs/python.md; the typed API the .pyi
stubs next to this file.
"""
import sys as _sys

from ._surfgrad import *  # noqa: F401,F403 (the extension defines __all__'s names)
from ._surfgrad import InputError, __version__, features, normalmap  # noqa: F401

# `import surfgrad.normalmap` and `from surfgrad.features import bake` work
# like for any package: the submodules are the extension's.
_sys.modules[__name__ + ".normalmap"] = normalmap
_sys.modules[__name__ + ".features"] = features
