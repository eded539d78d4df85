// The acquisition tests' bench: a ScannerDevice on the scripted LD, its tilt port kept by the
// test, and counts of what the LD was asked.
#pragma once

#include <algorithm>
#include <memory>

#include "ldoem/driver/scanner_device.hpp"
#include "ldoem/protocol/service_codes.hpp"
#include "scripted_ld.hpp"

namespace ldoem::test {

struct ScannerBench {
  std::shared_ptr<TiltLptPort> port = std::make_shared<TiltLptPort>();
  ScriptedLd ld;
  std::unique_ptr<driver::ScannerDevice> device;
  int transports_opened = 0;

  explicit ScannerBench(ScriptedLd::RangeFunction range)
      : ld(std::move(range), [this] { return port->position_half_steps(); }) {
    driver::TransportFactory transport = [this]() -> driver::Expected<std::unique_ptr<driver::TelegramTransport>, driver::DriverError> {
      ++transports_opened;
      return std::unique_ptr<driver::TelegramTransport>(std::make_unique<ScriptedTransport>(ld));
    };
    driver::LptFactory lpt = [this]() -> driver::Expected<std::unique_ptr<driver::LptPort>, driver::DriverError> {
      return std::unique_ptr<driver::LptPort>(std::make_unique<SharedTiltPort>(port));
    };
    device = std::make_unique<driver::ScannerDevice>("bench", transport, lpt, std::make_unique<VirtualSleeper>());
  }
  // The factories above hold `this`.
  ScannerBench(const ScannerBench&) = delete;
  ScannerBench& operator=(const ScannerBench&) = delete;

  std::size_t count(protocol::Service service) const {
    return static_cast<std::size_t>(
        std::count(ld.requests.begin(), ld.requests.end(), static_cast<std::uint16_t>(service)));
  }
};

}  // namespace ldoem::test
