// errormodel/src/json_input.cpp — the SAX guard of vcmm's JSON readers (see the header).
#include "vcmm/errormodel/json_input.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <set>
#include <vector>

namespace vcmm::errormodel {
namespace {

using json = nlohmann::json;

std::size_t line_of_byte(std::string_view text, std::size_t byte) {
  std::size_t line = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i)
    if (text[i] == '\n') ++line;
  return line;
}

/// Follows the JSON path of every token (arrays: "[i]", objects: ".key").
class PathTracker final : public nlohmann::json_sax<json> {
 public:
  explicit PathTracker(JsonInputCheck& out) : out_(out) {}

  struct Frame {
    bool is_array = false;
    std::size_t count = 0;  // arrays: elements started so far
    std::string key;        // objects: the current key
    std::set<std::string> keys;
  };

  // The JSON path through the first `depth` frames: array frames give "[i]" (the element
  // being parsed; `pending`: the top array's next element, whose first token failed to parse),
  // object frames their current key.
  std::string path(std::size_t depth, bool pending) const {
    std::string p;
    for (std::size_t f = 0; f < depth && f < frames_.size(); ++f) {
      const Frame& fr = frames_[f];
      if (fr.is_array) {
        const bool top = f + 1 == frames_.size();
        const std::size_t i = top && pending ? fr.count : (fr.count ? fr.count - 1 : 0);
        // Appended piecewise: "[" + to_string(i) + "]" trips a false GCC 12 -Wrestrict at -O3.
        p += '[';
        p += std::to_string(i);
        p += ']';
      } else {
        if (!p.empty()) p += '.';
        p += fr.key;
      }
    }
    return p;
  }

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t& s) override {
    value();
    if (!frames_.empty() && !frames_.back().is_array && frames_.back().key == "id")
      out_.ids[path(frames_.size() - 1, false)] = s;
    return true;
  }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(false); }
  bool key(string_t& k) override {
    Frame& fr = frames_.back();
    if (!fr.keys.insert(k).second && out_.problem == JsonInputCheck::Problem::none) {
      out_.problem = JsonInputCheck::Problem::duplicate_key;
      out_.path = path(frames_.size() - 1, false);
      out_.message = k;
    }
    fr.key = k;
    return true;
  }
  bool end_object() override {
    frames_.pop_back();
    return true;
  }
  bool start_array(std::size_t) override { return open(true); }
  bool end_array() override {
    frames_.pop_back();
    return true;
  }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& ex) override {
    std::string what = ex.what();
    if (const auto close = what.find("] "); what.rfind("[json.exception", 0) == 0 &&
                                            close != std::string::npos)
      what = what.substr(close + 2);
    out_.problem = JsonInputCheck::Problem::syntax;
    out_.path = path(frames_.size(), !frames_.empty() && frames_.back().is_array);
    out_.message = what;
    error_position_ = position;
    return false;
  }

  std::optional<std::size_t> error_position_;

 private:
  bool value() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().count;
    return true;
  }
  bool open(bool is_array) {
    value();
    if (frames_.size() >= max_json_depth) {
      out_.problem = JsonInputCheck::Problem::too_deep;
      out_.path = path(frames_.size(), false);
      out_.message = "nesting deeper than " + std::to_string(max_json_depth) + " levels";
      return false;  // stops the parse
    }
    frames_.push_back({is_array, 0, {}, {}});
    return true;
  }
  JsonInputCheck& out_;
  std::vector<Frame> frames_;
};

/// The byte offset of the first opening bracket beyond max_json_depth levels (strings
/// skipped), for the line of a too-deep value.
std::size_t too_deep_offset(std::string_view text) {
  std::size_t depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '[' || c == '{') {
      if (++depth > max_json_depth) return i;
    } else if (c == ']' || c == '}') {
      if (depth > 0) --depth;
    }
  }
  return text.size();
}

}  // namespace

JsonInputCheck check_json_input(std::string_view text) {
  JsonInputCheck out;
  PathTracker tracker(out);
  json::sax_parse(text, &tracker);
  if (out.problem == JsonInputCheck::Problem::syntax && tracker.error_position_)
    out.line = line_of_byte(text, *tracker.error_position_ > 0 ? *tracker.error_position_ - 1 : 0);
  if (out.problem == JsonInputCheck::Problem::too_deep)
    out.line = line_of_byte(text, too_deep_offset(text));
  return out;
}

}  // namespace vcmm::errormodel
