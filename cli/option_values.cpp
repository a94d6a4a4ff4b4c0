// cli/option_values.cpp — see option_values.h.
#include "option_values.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace vcmm::cli {

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          std::size_t used = 0;
          const double v = std::stod(text, &used);
          if (used != text.size()) return "'" + text + "' is not a number";
          if (!std::isfinite(v)) return "'" + text + "' is not a finite number";
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        return {};
      },
      "FINITE");
}

CLI::Validator unsigned_64() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        static const std::string kMax = "18446744073709551615";
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        std::string trimmed = text.substr(std::min(text.find_first_not_of('0'), text.size()));
        if (trimmed.empty()) trimmed = "0";
        if (!digits || trimmed.size() > kMax.size() ||
            (trimmed.size() == kMax.size() && trimmed > kMax))
          return "'" + text + "' is not an unsigned 64-bit integer (0 to " + kMax + ")";
        return {};
      },
      "UINT64");
}

Eigen::Vector3d parse_triple(const std::string& text, const char* option) {
  Eigen::Vector3d v;
  std::size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t comma = text.find(',', start);
    if ((k < 2) != (comma != std::string::npos))
      throw std::invalid_argument(std::string(option) + " needs three comma-separated numbers " +
                                  "X,Y,Z (mm); got '" + text + "'");
    std::string field = text.substr(start, k < 2 ? comma - start : std::string::npos);
    while (!field.empty() && field.front() == ' ') field.erase(0, 1);
    while (!field.empty() && field.back() == ' ') field.pop_back();
    if (!field.empty() && field.front() == '+') field.erase(0, 1);
    const auto r = std::from_chars(field.data(), field.data() + field.size(), v[k]);
    if (field.empty() || r.ec != std::errc() || r.ptr != field.data() + field.size() ||
        !std::isfinite(v[k]))
      throw std::invalid_argument(std::string(option) + ": component " + std::to_string(k + 1) +
                                  " is not a finite number ('" + field + "')");
    start = comma + 1;
  }
  return v;
}

std::optional<double> parse_filter_upr(const std::string& text) {
  if (upper_case(text) == "NONE") return std::nullopt;
  std::size_t used = 0;
  double upr = 0.0;
  try {
    upr = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(upr) || upr <= 0.0)
    throw std::invalid_argument("--filter-upr must be a positive number of UPR or 'none'; got '" +
                                text + "'");
  return upr;
}

double millimetres_per_unit(const std::string& unit) {
  if (unit == "mm") return 1.0;
  if (unit == "um") return 1e-3;
  if (unit == "in") return 25.4;
  throw std::invalid_argument("--unit must be mm, um or in; got '" + unit + "'");
}

std::string upper_case(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += "\"\"";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out + "\"";
}

}  // namespace vcmm::cli
