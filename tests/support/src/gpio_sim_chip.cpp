#include "ldoem/test_support/gpio_sim_chip.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>

namespace ldoem::test_support {

std::optional<SimChip> sim_chip(std::string& why_not) {
  const char* label = std::getenv("LDOEM_GPIO_LABEL");
  const char* sysfs = std::getenv("LDOEM_GPIO_SIM_SYSFS");
  if (label != nullptr && sysfs != nullptr) return SimChip{label, sysfs};
  char env_file[] = "/tmp/ldoem-gpio-env.XXXXXX";
  const int fd = ::mkstemp(env_file);
  if (fd < 0) {
    why_not = "mkstemp failed";
    return std::nullopt;
  }
  ::close(fd);
  const std::string command = std::string(LDOEM_GPIO_SIM_SETUP) + " " + env_file + " 2>&1";
  const int status = std::system(command.c_str());
  std::map<std::string, std::string> values;
  std::ifstream lines(env_file);
  for (std::string line; std::getline(lines, line);) {
    const auto equals = line.find('=');
    if (line.rfind("export ", 0) == 0 && equals != std::string::npos) {
      values[line.substr(7, equals - 7)] = line.substr(equals + 1);
    }
  }
  ::unlink(env_file);
  if (status != 0 || !values.contains("LDOEM_GPIO_LABEL") || !values.contains("LDOEM_GPIO_SIM_SYSFS")) {
    why_not = command + " failed (gpio tests run in the gpio-sim UML kernel: scripts/uml/run.sh --kernel "
              "\"$(scripts/uml/build-gpio-kernel.sh)\" --gpio -- ctest -L gpio)";
    return std::nullopt;
  }
  return SimChip{values["LDOEM_GPIO_LABEL"], values["LDOEM_GPIO_SIM_SYSFS"]};
}

bool pull_sim_line(const SimChip& chip, int line, bool up) {
  const std::string path = chip.sysfs + "/sim_gpio" + std::to_string(line) + "/pull";
  std::ofstream attribute(path);
  attribute << (up ? "pull-up" : "pull-down") << std::flush;
  return attribute.good();
}

}  // namespace ldoem::test_support
