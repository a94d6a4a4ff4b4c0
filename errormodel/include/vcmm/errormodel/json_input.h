// vcmm/errormodel/json_input.h — the guard every vcmm JSON reader runs over a file's text
// before building a document from it (model files, kinematics sections, campaigns).
//
// nlohmann's DOM keeps the last of two equal keys silently, turns a number beyond the double
// range (1e999) into an exception without a file name, and a deeply nested value (100 000 "[")
// exhausts the stack of any code that walks or prints it recursively. One SAX pass over the
// text (nlohmann's SAX parser keeps its own stack: it does not recurse) finds each of these
// with the line and the JSON path where it happens; each reader turns the finding into its own
// error type with its own wording of the source.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>

namespace vcmm::errormodel {

/// Nesting allowed in vcmm's JSON files: the deepest legitimate file nests 6 levels.
inline constexpr std::size_t max_json_depth = 64;

struct JsonInputCheck {
  enum class Problem {
    none,
    syntax,         ///< not valid JSON, or a number outside the double range (message: why)
    duplicate_key,  ///< a key appears twice in one object (message: the key)
    too_deep,       ///< nesting deeper than max_json_depth
  };
  Problem problem = Problem::none;
  std::string path;      ///< where: the dotted JSON path ("measurements[3].setup"; "" = root)
  std::string message;   ///< the parser's words (syntax) or the repeated key
  std::size_t line = 0;  ///< 1-based line of the problem (0 when not known)
  /// The "id" string of every object that has one, by the object's path
  /// ({"measurements[3]": "C-O000-top-scan"}): lets a reader name the entry of a problem.
  std::map<std::string, std::string> ids;

  bool ok() const { return problem == Problem::none; }
};

/// One SAX pass over `text` (file comment). O(size of the text); never recurses.
JsonInputCheck check_json_input(std::string_view text);

}  // namespace vcmm::errormodel
