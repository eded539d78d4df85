// libFuzzer target: the endpoint grammar (base/endpoint.hpp, docs/endpoints.md). For every side
// and every kind an option may expect: a text that parses formats back (to_string) to a text
// that parses to the same endpoint of the same kind; a text that fails gives a one-line
// message, and an old spelling's suggestion parses.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "ldoem/base/endpoint.hpp"

namespace b = ldoem::base;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (const b::EndpointSide side : {b::EndpointSide::offer, b::EndpointSide::connect}) {
    for (const b::EndpointExpect expect : {b::EndpointExpect::any, b::EndpointExpect::scanner, b::EndpointExpect::can,
                                           b::EndpointExpect::tcp, b::EndpointExpect::serial, b::EndpointExpect::lpt}) {
      const b::EndpointUse use{side, expect};
      const auto parsed = b::parse_endpoint(text, use);
      if (parsed) {
        const auto again = b::parse_endpoint(b::to_string(*parsed), use);
        if (!again || !(*again == *parsed)) std::abort();
        continue;
      }
      const std::string line = b::describe_for_option("--x", parsed.error());
      if (line.empty()) std::abort();
      if (parsed.error().kind == b::EndpointErrorKind::old_spelling && !b::parse_endpoint(parsed.error().suggestion, use)) {
        std::abort();
      }
    }
  }
  return 0;
}
