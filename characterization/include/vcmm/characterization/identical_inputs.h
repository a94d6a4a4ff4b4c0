// vcmm/characterization/identical_inputs.h — a calibration input given twice (the same file
// for two placements, or as a scan and its repeat) is a blunder that the fits cannot see: two
// identical placements look like a perfectly repeatable machine, an identical repeat scan like a
// noise-free one. Refused before anything is fitted (docs/characterization.md, "Consistency of
// a calibration").
#pragma once

#include <span>
#include <string>

namespace vcmm::characterization {

/// One input file as the user gave it.
struct InputFile {
  std::string argument;  ///< the option that named it, e.g. "--placement" or "--scan-repeat"
  std::string path;
};

/// Throws errormodel::InvalidInput when two of `files` have the same content byte for byte
/// (also when they are one file reached through two paths or links), naming both arguments
/// and paths: "--placement a.csv and --placement b.csv have identical content …". Files that
/// cannot be read are skipped (their reader reports them). Compares a hash of the content
/// first, then the bytes. O(total size).
void refuse_identical_inputs(std::span<const InputFile> files);

}  // namespace vcmm::characterization
