// python/src/bindings.h — what the two translation units of the extension vcmm._vcmm share:
// the numpy ↔ point conversions and the registration of the uncertainty bindings.
// The extension converts and forwards; every feature lives in the C++ library.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <span>
#include <vector>

#include "vcmm/geometry/point.h"

namespace vcmm::python {

namespace py = pybind11;

/// Points from an (n, 2) or (n, 3) array-like of x, y[, z] in mm (numpy array, list of
/// pairs...): x and y of every row, z dropped. An empty sequence gives no points (the library
/// then names the rule). Anything else: geometry::InvalidInput naming `what` and the shape.
std::vector<geometry::Point2> points_from_array(const py::handle& object, const char* what);
/// The same, keeping z (0 for an (n, 2) array) in `z`.
std::vector<geometry::Point2> points_from_array(const py::handle& object, const char* what,
                                                std::vector<double>& z);

/// An (n, 2) float64 array of the points.
py::array_t<double> points_to_array(std::span<const geometry::Point2> points);

/// Registers simulate, uncertainty and their types (uncertainty_bindings.cpp).
void bind_uncertainty(py::module_& m);

}  // namespace vcmm::python
