"""The parts of the hovox package written in Python on top of the extension (called from it)."""
import os
import shutil
import tempfile

from . import _hovox


def layer_image(model, mesh, index, **options):
    """Model.layer: printer layer `index` written as a one-layer stack (the same bytes as the full
    stack's layer: every layer range gives the full run's files) and read back."""
    if "layers" in options:
        raise TypeError("layer() takes the layer's index, not layers=")
    index = int(index)
    if index < 0:
        raise _hovox.InvalidError("index must be >= 0, got %d" % index)
    work = tempfile.mkdtemp(prefix="hovox-layer-")
    try:
        stack = os.path.join(work, "stack")
        model.layers(mesh, stack, layers=(index, index + 1), **options)
        name = "layer-%05d.png" % index
        if os.path.exists(os.path.join(stack, name)):
            image = _hovox.read_png(os.path.join(stack, name), indices=True)
            if options.get("mode") == "mask":  # 1-bit grey, read back as 0 or 255: the bits, 1 = object
                image = (image > 0).astype(image.dtype)
            return image  # halftone: the palette indices
        # fractions mode: one directory per material, in the model's order
        import numpy
        names = model.materials().names()
        return numpy.stack([_hovox.read_png(os.path.join(stack, m, name)) for m in names])
    finally:
        shutil.rmtree(work, ignore_errors=True)
