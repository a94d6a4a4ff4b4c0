// Identical calibration inputs (identical_inputs.h).
#include "vcmm/characterization/identical_inputs.h"

#include <cstddef>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <string>
#include <utility>
#include <string_view>
#include <vector>

#include "vcmm/errormodel/errors.h"
#include "vcmm/geometry/text_file.h"

namespace vcmm::characterization {

void refuse_identical_inputs(std::span<const InputFile> files) {
  std::vector<std::optional<std::string>> content(files.size());
  std::vector<std::size_t> hash(files.size(), 0);
  for (std::size_t i = 0; i < files.size(); ++i) {
    std::string text, reason;  // an unreadable file is left to its reader, which names it
    if (!geometry::try_read_text_file(files[i].path, text, reason)) continue;
    content[i].emplace(std::move(text));
    hash[i] = std::hash<std::string_view>{}(*content[i]);
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (!content[i]) continue;
    for (std::size_t j = 0; j < i; ++j) {
      if (!content[j] || hash[j] != hash[i] || *content[j] != *content[i]) continue;
      const InputFile& a = files[j];
      const InputFile& b = files[i];
      const bool same_path = a.path == b.path;
      throw errormodel::InvalidInput(
          a.argument + " " + a.path + " and " + b.argument + " " + b.path +
          (same_path ? " are the same file" : " have identical content (byte for byte)") +
          ": one measurement given twice; a calibration needs independent measurements");
    }
  }
}

}  // namespace vcmm::characterization
