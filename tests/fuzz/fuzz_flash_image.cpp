// libFuzzer target: the flash image parser (emulator/device/control, D4). The format is strict ("a
// file that deviates in any way is refused"), so any image it accepts must be exactly what
// serialise_flash_image writes for the configuration it read.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ldoem/control/flash_image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ldoem::protocol::ByteView image(data, size);
  const auto parsed = ldoem::control::parse_flash_image(image);
  if (!parsed) {
    (void)ldoem::control::describe(parsed.error().kind);
    return 0;
  }
  const ldoem::protocol::Bytes written = ldoem::control::serialise_flash_image(*parsed);
  if (written.size() != size || !std::equal(written.begin(), written.end(), data)) std::abort();
  return 0;
}
