// A rendered image as Python sees it: a penumbra.Layers (a dict of numpy arrays by layer
// name, python/penumbra/__init__.py) whose .meta holds the EXR header attributes. Layers:
// "rgb", float32 (height, width, 3), then the AOVs (SCENE_FORMAT.md "AOVs (v3)") in
// film.aovs' order: float32 (height, width, 3) for albedo, normal, position and variance,
// float32 (height, width) for depth, uint32 (height, width) for the ids. Each layer's dtype
// and shape are written here alone, both ways (channels: image/aov_channels.h).
#pragma once

#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "image/image.h"

namespace penumbra::python {

// The layers and metadata of `image` (its pixels moved into the arrays, not copied).
pybind11::object layersFromImage(Image&& image);

// The Image that `layers` describes, for write_exr: a mapping with "rgb" (any array-like
// of shape (height, width, 3), converted to float32), any AOV layers (shapes as above;
// ids must be unsigned integers) and, if it has one, a .meta dict (keys as in
// layersFromImage; absent keys are left out of the header). Unknown layers, other shapes
// or metadata keys raise ValueError naming them.
Image imageFromLayers(pybind11::handle layers);

// layers[name] (an AOV) as the preview shows it (image/aov_false_color.h): linear float32
// (height, width, 3) that write_png turns into that picture. KeyError if it has no such layer.
pybind11::array_t<float> falseColor(pybind11::handle layers, const std::string& name);

}  // namespace penumbra::python
