// GpioLptPort on the gpio-sim chip of D8 (ctest label `gpio`, run inside the gpio-sim UML
// kernel with scripts/uml/run.sh --gpio). Inside UML (LDOEM_IN_UML set by the harness) it FAILS
// when the chip's variables are missing; on a plain host, which has no gpio-sim, it skips.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "ldoem/driver/lpt_port.hpp"

namespace ldoem::driver {
namespace {

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value == nullptr ? std::string() : std::string(value);
}

// The level gpio-sim shows for a line that a user drives as an output.
int sim_level(const std::string& sysfs, int offset) {
  std::ifstream in(sysfs + "/sim_gpio" + std::to_string(offset) + "/value");
  int level = -1;
  in >> level;
  return level;
}

TEST(GpioLptPort, RegisterWrites_DriveTheNamedLines) {
  const std::string label = environment("LDOEM_GPIO_LABEL");
  const std::string sysfs = environment("LDOEM_GPIO_SIM_SYSFS");
  if ((label.empty() || sysfs.empty()) && environment("LDOEM_IN_UML").empty()) {
    GTEST_SKIP() << "no gpio-sim chip outside UML: run through scripts/uml/run.sh --gpio";
  }
  ASSERT_FALSE(label.empty() || sysfs.empty())
      << "LDOEM_GPIO_LABEL / LDOEM_GPIO_SIM_SYSFS unset: run through scripts/uml/run.sh --gpio";
  auto port = open_lpt_port(LptEndpoint{LptBackend::gpio, label});
  ASSERT_TRUE(port) << describe(port.error());
  for (std::uint8_t value : {0x05, 0x07, 0x02, 0x00}) {
    ASSERT_TRUE((*port)->write_data(value));
    EXPECT_EQ(sim_level(sysfs, 0), (value >> 0) & 1) << "DIR after " << int{value};
    EXPECT_EQ(sim_level(sysfs, 1), (value >> 1) & 1) << "CLK after " << int{value};
    EXPECT_EQ(sim_level(sysfs, 2), (value >> 2) & 1) << "MODE after " << int{value};
  }
}

}  // namespace
}  // namespace ldoem::driver
