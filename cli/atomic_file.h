// cli/atomic_file.h — the CLI writes its results with the library's atomic writer; the files
// of one command through one OutputTransaction.
#pragma once

#include "vcmm/errormodel/atomic_file.h"

namespace vcmm::cli {
using errormodel::check_output_path;
using errormodel::OutputTransaction;
using errormodel::write_file_atomically;
}  // namespace vcmm::cli
