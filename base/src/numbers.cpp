#include "ldoem/base/numbers.hpp"

#include <cmath>

namespace ldoem::base {

std::optional<double> parse_double(std::string_view text, NonFinite non_finite) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc{} || stop != end) {
    return std::nullopt;
  }
  if (non_finite == NonFinite::reject && !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

}  // namespace ldoem::base
