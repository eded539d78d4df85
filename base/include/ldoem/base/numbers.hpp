// Numbers read from text (command lines, hub lines, YAML scalars, cloud files): the whole text
// must be the number, in std::from_chars' grammar (no spaces, no leading '+', no "0x").
// Anything else, out-of-range values included, gives no value, and the caller says why.
#pragma once

#include <charconv>
#include <concepts>
#include <optional>
#include <string_view>

namespace ldoem::base {

// Decimal by default; base 16 reads "1A" and "1a".
template <std::integral Integer>
[[nodiscard]] std::optional<Integer> parse_integer(std::string_view text, int base = 10) {
  Integer value{};
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value, base);
  if (text.empty() || error != std::errc{} || stop != end) {
    return std::nullopt;
  }
  return value;
}

// Whether "nan", "inf" and "-inf" count as numbers: options and protocol fields want finite
// values; point-cloud files store NaN for "no echo".
enum class NonFinite { reject, accept };

[[nodiscard]] std::optional<double> parse_double(std::string_view text, NonFinite non_finite = NonFinite::reject);

}  // namespace ldoem::base
