// The parallel-port data register that drives the tilt stepper board (D8), behind one small
// interface: a real port through ppdev, a pseudo terminal or file (each byte = the new
// register value), or three GPIO output lines through libgpiod v1.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "ldoem/driver/endpoint.hpp"
#include "ldoem/driver/error.hpp"

namespace ldoem::driver {

class LptPort {
 public:
  virtual ~LptPort() = default;
  // Sets the data register to `value` (D8 bits: DATA0 DIR, DATA1 CLK, DATA2 MODE).
  virtual Status write_data(std::uint8_t value) = 0;
  virtual const std::string& name() const = 0;
};

// /dev/parportN: open, PPCLAIM, PPWDATA per write, PPRELEASE on destruction.
class PpdevLptPort final : public LptPort {
 public:
  static Expected<std::unique_ptr<PpdevLptPort>, DriverError> open(const std::string& path);
  ~PpdevLptPort() override;
  PpdevLptPort(const PpdevLptPort&) = delete;
  PpdevLptPort& operator=(const PpdevLptPort&) = delete;
  Status write_data(std::uint8_t value) override;
  const std::string& name() const override { return name_; }

 private:
  PpdevLptPort(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  int fd_;
  std::string name_;
};

// A pty (or any file): opened O_WRONLY | O_NOCTTY, one byte written per register change (D8).
// A terminal is put in raw mode so that no byte is translated on its way.
class PtyLptPort final : public LptPort {
 public:
  static Expected<std::unique_ptr<PtyLptPort>, DriverError> open(const std::string& path);
  ~PtyLptPort() override;
  PtyLptPort(const PtyLptPort&) = delete;
  PtyLptPort& operator=(const PtyLptPort&) = delete;
  Status write_data(std::uint8_t value) override;
  const std::string& name() const override { return name_; }

 private:
  PtyLptPort(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  int fd_;
  std::string name_;
};

// libgpiod v1.6: output lines named DIR, CLK, MODE on the chip (found by label, name, path or
// number); a chip without those names uses offsets 0, 1, 2. Each write changes only the lines
// whose bit changed, DIR and MODE before CLK, so a rising clock edge sees the new direction.
class GpioLptPort final : public LptPort {
 public:
  static constexpr const char* kDirectionLineName = "DIR";
  static constexpr const char* kClockLineName = "CLK";
  static constexpr const char* kModeLineName = "MODE";

  static Expected<std::unique_ptr<GpioLptPort>, DriverError> open(const std::string& chip);
  ~GpioLptPort() override;
  GpioLptPort(const GpioLptPort&) = delete;
  GpioLptPort& operator=(const GpioLptPort&) = delete;
  Status write_data(std::uint8_t value) override;
  const std::string& name() const override { return name_; }

 private:
  struct Lines;
  GpioLptPort(std::unique_ptr<Lines> lines, std::string name);
  std::unique_ptr<Lines> lines_;
  std::string name_;
  std::uint8_t last_value_ = 0;
};

// Opens the port an `lpt:` endpoint names; any other endpoint is invalid_argument.
Expected<std::unique_ptr<LptPort>, DriverError> open_lpt_port(const Endpoint& endpoint);

}  // namespace ldoem::driver
