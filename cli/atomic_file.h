// cli/atomic_file.h — the CLI writes its results with the library's atomic writer.
#pragma once

#include "vcmm/errormodel/atomic_file.h"

namespace vcmm::cli {
using errormodel::write_file_atomically;
}  // namespace vcmm::cli
