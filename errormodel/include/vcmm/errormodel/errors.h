// vcmm/errormodel/errors.h — the exceptions thrown at the public boundary of vcmm::errormodel.
//
// Both derive from std::invalid_argument, so a caller that only wants "bad input" can catch
// that. Messages follow docs/errormodel.md: "<function or file:line>: <rule>; <offending
// value>", and for the digital-model file the full key path ("probe.tip_radius_error_um.u").
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

#include "vcmm/geometry/point.h"

namespace vcmm::errormodel {

/// A measurement, an option or a measurement file that cannot be used: NaN/inf coordinates,
/// normals that are not unit vectors, mismatched sizes, an unparsable CSV line. The message
/// names the function or the file and 1-based line, the rule and the offending value. The
/// same type as vcmm::geometry::InvalidInput: one "bad input" exception for the library.
using InvalidInput = vcmm::geometry::InvalidInput;

/// A digital-model parameter file that breaks its schema: a missing, unknown, negative,
/// non-numeric or non-finite entry, or a wrong schema/version. `key_path()` is the full dotted
/// path of the offending entry ("noise.scanning_sigma_um"); the message also carries the value
/// and the rule broken.
class InvalidParameter : public InvalidInput {
 public:
  InvalidParameter(std::string key_path, const std::string& message)
      : InvalidInput(message), key_path_(std::move(key_path)) {}
  const std::string& key_path() const noexcept { return key_path_; }

 private:
  std::string key_path_;
};

}  // namespace vcmm::errormodel
