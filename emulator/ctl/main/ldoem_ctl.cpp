// ldoem-ctl: parse, connect, send, print (docs/faults.md). Exit 0/1/2.
#include <iostream>

#include "ldoem/ctl/ctl_client.hpp"

int main(int argc, char** argv) {
  using namespace ldoem::ctl;
  const std::vector<std::string> args(argv + 1, argv + argc);
  auto parsed = parse_ctl_options(args);
  if (auto* exit = std::get_if<CtlExit>(&parsed)) {
    (exit->code == kExitOk ? std::cout : std::cerr) << exit->text << (exit->text.ends_with('\n') ? "" : "\n");
    return exit->code;
  }
  return run_ctl(std::get<CtlPlan>(parsed), std::cout, std::cerr);
}
