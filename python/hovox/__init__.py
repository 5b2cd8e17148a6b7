"""hovox: heterogeneous-object modeling for multi-material 3D printing, after Xiaojun Wu, from Python.

The C library's API (what the Lua API reaches, README "Python"): meshes (load_mesh, mesh, generate,
join_meshes, Mesh.transform), voxelize, materials, features (point, axis, plane, halfspace, segment, facets,
Model.contour/mask/field/harmonic), sources (ags, wu3; f may be a Python callable, tabulated once),
objects and their Booleans (object; & | - +), evaluation (grading), probe, profile, render, contours,
layers, tray and export, with NumPy arrays in and out: Model.fractions() and friends (dense),
Model.leaves() (sparse, without a copy), Model.field(values=array), probe points as (n, 3) arrays,
renders and layers as image arrays.

Options are keyword arguments named as the CLI's long options with '_' for '-' (layer_height is
--layer-height), read and refused by the library's option sets with the CLI's messages. Errors are
hovox.Error subclasses, one per status (InvalidError, BadInputError, FileError, NoMemoryError,
LimitError, CancelledError, NotFoundError, UnsupportedError, InternalError; ClosedError for a freed
object). Long calls release the GIL, take progress=callable(stage, fraction) and stop on Ctrl-C
(KeyboardInterrupt)."""
from . import _hovox
from ._hovox import (  # noqa: F401
    BadInputError,
    CancelledError,
    ClosedError,
    Error,
    Feature,
    FileError,
    InternalError,
    InvalidError,
    LimitError,
    Materials,
    Mesh,
    Model,
    NoMemoryError,
    NotFoundError,
    Object,
    Source,
    Tray,
    UnsupportedError,
    ags,
    axis,
    contours,
    facets,
    halfspace,
    join_meshes,
    layers_scan,
    line,
    load,
    load_mesh,
    materials,
    mesh,
    object,
    plane,
    point,
    read_png,
    rgba8,
    segment,
    set_threads,
    shapes,
    status_name,
    threads,
    tray,
    version,
    voxelize,
    wu3,
)

__version__ = version


class _Generate:
    """Parametric closed meshes, the shapes and keys of `hovox generate`: generate.gear(teeth=24, ...),
    generate.holed_box(...), or generate("holed-box", ...). hovox.shapes() lists them with their keys."""

    def __call__(self, shape, **params):
        return _hovox.generate(shape, **params)

    def __getattr__(self, name):
        shape = name.replace("_", "-")
        if shape not in _hovox.shapes():
            raise AttributeError("hovox.generate has no shape %r (shapes: %s)" % (name, ", ".join(_hovox.shapes())))

        def make(**params):
            return _hovox.generate(shape, **params)

        make.__name__ = name
        make.__doc__ = "%s: %s (keys: %s)" % ((shape,) + tuple(_hovox.shapes()[shape][:1]) +
                                             (", ".join(_hovox.shapes()[shape][1]),))
        return make

    def __dir__(self):
        return [s.replace("-", "_") for s in _hovox.shapes()]


generate = _Generate()
