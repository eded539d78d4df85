// The emulated flash (D4): the DeviceConfig as a small versioned text file, and the store the
// daemon keeps it in. The control unit never writes a file: it hands the new image to the
// daemon in Actions::flash_image, and reads an image only through parse_flash_image.
//
// Format, version 1 (ASCII, one record per line, fields separated by single spaces, every
// record exactly once and in this order, numbers decimal):
//   ldoem-flash 1
//   global SENSOR_ID MOTOR_SPEED_HZ ANGLE_STEP_TICKS
//   interlace MODE
//   ethernet IP0 IP1 IP2 IP3 MASK0 MASK1 MASK2 MASK3 GW0 GW1 GW2 GW3 NODE_ID TCP_PORT
//   serial BAUD_CODE PARITY STOP_BITS DATA_BITS
//   can BITRATE_CODE REQUEST_ID RESPONSE_ID BLOCK_SIZE ST_MIN_MS
//   filter 0|1
//   sector N FUNCTION STOP_TICKS        (8 lines, N = 0..7)
//   end
// Example (the D4 defaults) is what serialise_flash_image(factory_config()) returns; the tests
// hold it verbatim. A file that deviates in any way is refused with a typed error, and the
// daemon then starts from the defaults and warns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "ldoem/control/device_config.hpp"
#include "ldoem/protocol/bytes.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::control {

inline constexpr std::string_view kFlashMagic = "ldoem-flash";
inline constexpr unsigned kFlashFormatVersion = 1;

enum class FlashErrorKind : std::uint8_t {
  empty,                // no bytes at all (no flash written yet)
  bad_magic,            // first line is not "ldoem-flash <version>"
  unsupported_version,  // a version this build does not read
  malformed_line,       // wrong record name or order, wrong field count, not a number, no newline
  value_out_of_range,   // a number outside its WORD or a value SET_CONFIG would refuse
  trailing_data,        // bytes after "end"
};

struct FlashError {
  FlashErrorKind kind = FlashErrorKind::malformed_line;
  std::size_t line = 0;  // 1-based line of the problem; 0 when not tied to a line
  bool operator==(const FlashError&) const = default;
};

std::string_view describe(FlashErrorKind kind);

protocol::Bytes serialise_flash_image(const DeviceConfig& config);
base::Expected<DeviceConfig, FlashError> parse_flash_image(protocol::ByteView image);

// Where the daemon keeps the image: a file in the state folder, or memory with --no-flash (D4).
class FlashStore {
 public:
  // Nothing, or why the image was not stored (the file, the step, the OS error).
  using Saved = base::Expected<std::monostate, std::string>;
  virtual ~FlashStore() = default;
  // The stored bytes; empty when nothing was ever saved.
  virtual protocol::Bytes load() const = 0;
  // An error when the image was not stored (a file store: a removed folder, a full disk).
  virtual Saved save(protocol::ByteView image) = 0;
};

class MemoryFlashStore final : public FlashStore {
 public:
  protocol::Bytes load() const override { return image_; }
  Saved save(protocol::ByteView image) override {
    image_.assign(image.begin(), image.end());
    return std::monostate{};
  }

 private:
  protocol::Bytes image_;
};

// What the daemon does at start: the stored configuration, or `defaults` plus the reason the
// stored one was unusable (empty store is FlashErrorKind::empty, not worth a warning).
struct FlashLoadResult {
  DeviceConfig config;
  std::optional<FlashError> problem;
};
FlashLoadResult load_flash_or(const FlashStore& store, const DeviceConfig& defaults);

}  // namespace ldoem::control
