// A rendered image as Python sees it: a penumbra.Layers (a dict of numpy arrays by layer
// name, python/penumbra/__init__.py) whose .meta holds the EXR header attributes. Layers
// today: "rgb", float32 (height, width, 3). Each layer's name, dtype and shape are written
// here alone, both ways, so a new layer is one entry in each direction.
#pragma once

#include <string>

#include <pybind11/pybind11.h>

#include "image/image.h"

namespace penumbra::python {

// The layers and metadata of `image` (its pixels moved into the arrays, not copied).
pybind11::object layersFromImage(Image&& image);

// The Image that `layers` describes, for write_exr: a mapping with "rgb" (any array-like
// of shape (height, width, 3), converted to float32) and, if it has one, a .meta dict
// (keys as in layersFromImage; absent keys are left out of the header). Unknown layers or
// metadata keys raise ValueError naming them.
Image imageFromLayers(pybind11::handle layers);

}  // namespace penumbra::python
