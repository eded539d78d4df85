// libFuzzer: the candump log parser on arbitrary text. Errors are typed with a line number
// inside the text; every parsed classic frame formats back to a line that parses to the same
// frame.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "ldoem/capture/candump_log.hpp"

using namespace ldoem::protocol;
using namespace ldoem::capture;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto entries = parse_candump_log(text);
  if (!entries) {
    std::size_t lines = 1;
    for (char c : text) lines += c == '\n' ? 1 : 0;
    if (entries.error().line == 0 || entries.error().line > lines) std::abort();
    return 0;
  }
  for (const auto& entry : *entries) {
    if (entry.frame.length > kCanMaxDataBytes) std::abort();
    if (entry.extended_id || entry.remote || entry.interface.find_first_of(" \t\n") != std::string::npos) continue;
    const auto again = parse_candump_line(format_candump_line(entry.time_ns, entry.interface, entry.frame));
    if (!again || !(again->frame == entry.frame) || again->interface != entry.interface) std::abort();
  }
  return 0;
}
