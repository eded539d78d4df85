// GPIO back end of the stepper port (D8) on libgpiod v1.6: three output lines.
#include <gpiod.h>

#include <array>
#include <cerrno>

#include "ldoem/driver/lpt_port.hpp"
#include "ldoem/protocol/lpt.hpp"

namespace ldoem::driver {
namespace {

constexpr const char* kConsumer = "ldoem-driver";

struct LineSpec {
  const char* name;
  unsigned fallback_offset;
  std::uint8_t bit;
};

// Order matters: DIR and MODE are set before CLK within one write (D8: the board samples them
// at the rising clock edge).
constexpr std::array<LineSpec, 3> kLines{{
    {GpioLptPort::kDirectionLineName, 0, protocol::kLptDirectionBit},
    {GpioLptPort::kModeLineName, 2, protocol::kLptModeBit},
    {GpioLptPort::kClockLineName, 1, protocol::kLptClockBit},
}};

}  // namespace

struct GpioLptPort::Lines {
  gpiod_chip* chip = nullptr;
  std::array<gpiod_line*, kLines.size()> lines{};

  ~Lines() {
    for (gpiod_line* line : lines) {
      if (line != nullptr) {
        gpiod_line_release(line);
      }
    }
    if (chip != nullptr) {
      gpiod_chip_close(chip);
    }
  }
};

GpioLptPort::GpioLptPort(std::unique_ptr<Lines> lines, std::string name)
    : lines_(std::move(lines)), name_(std::move(name)) {}

GpioLptPort::~GpioLptPort() = default;

Expected<std::unique_ptr<GpioLptPort>, DriverError> GpioLptPort::open(const std::string& chip) {
  const std::string object = "lpt:gpio:" + chip;
  auto lines = std::make_unique<Lines>();
  lines->chip = gpiod_chip_open_lookup(chip.c_str());
  if (lines->chip == nullptr) {
    return fail(system_error("gpiod_chip_open_lookup", object, errno != 0 ? errno : ENODEV));
  }
  // Named lines when the chip has all three names, otherwise offsets 0/1/2 (D8).
  bool all_named = true;
  std::array<gpiod_line*, kLines.size()> found{};
  for (std::size_t i = 0; i < kLines.size(); ++i) {
    found[i] = gpiod_chip_find_line(lines->chip, kLines[i].name);
    all_named = all_named && found[i] != nullptr;
  }
  for (std::size_t i = 0; i < kLines.size(); ++i) {
    gpiod_line* line = all_named ? found[i] : gpiod_chip_get_line(lines->chip, kLines[i].fallback_offset);
    if (line == nullptr) {
      return fail(system_error(std::string("gpiod line ") + kLines[i].name, object, errno != 0 ? errno : ENOENT));
    }
    if (gpiod_line_request_output(line, kConsumer, 0) != 0) {
      return fail(system_error(std::string("request output ") + kLines[i].name, object, errno));
    }
    lines->lines[i] = line;
  }
  return std::unique_ptr<GpioLptPort>(new GpioLptPort(std::move(lines), object));
}

Status GpioLptPort::write_data(std::uint8_t value) {
  const std::uint8_t changed = static_cast<std::uint8_t>(value ^ last_value_);
  for (std::size_t i = 0; i < kLines.size(); ++i) {
    if ((changed & kLines[i].bit) == 0) {
      continue;
    }
    const int level = (value & kLines[i].bit) != 0 ? 1 : 0;
    if (gpiod_line_set_value(lines_->lines[i], level) != 0) {
      return fail(system_error(std::string("set ") + kLines[i].name, name_, errno));
    }
    last_value_ = static_cast<std::uint8_t>((last_value_ & ~kLines[i].bit) | (value & kLines[i].bit));
  }
  return ok();
}

}  // namespace ldoem::driver
