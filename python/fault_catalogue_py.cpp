// Writes ldoem/_fault_catalogue.py at build time (python/CMakeLists.txt): the emulator's D11 fault
// catalogue (emulator/faults, fault_kind.hpp) as Python data, so that ldoem.faults keeps no copy
// of it by hand and stays pure Python (it runs under any interpreter, whether or not the
// extension module fits it). Not installed: only its output is.
#include <fstream>
#include <iostream>

#include "ldoem/faults/fault_kind.hpp"

namespace {

using namespace ldoem;

void write_fault_row(std::ostream& out, const faults::FaultKindInfo& kind) {
  out << "    (\"" << kind.name << "\", \"" << (kind.fault_class == faults::FaultClass::device ? "device" : "wire")
      << "\", (";
  for (std::size_t index = 0; index < protocol::kTransportCount; ++index) {
    const auto transport = static_cast<protocol::Transport>(index);
    if (kind.transports.contains(transport)) out << '"' << protocol::transport_name(transport) << "\", ";
  }
  out << "), " << (kind.extent == faults::FaultExtent::one_shot ? "True" : "False") << "),\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: " << argv[0] << " OUTPUT.py\n";
    return 2;
  }
  std::ofstream out(argv[1]);
  out << "\"\"\"Generated at build time from emulator/faults/include/ldoem/faults/fault_kind.hpp by\n"
         "python/fault_catalogue_py.cpp: do not edit.\n\n"
         "FAULT_CATALOGUE: one (name, class, transports, one_shot) tuple per D11 kind, in the\n"
         "catalogue's order: class \"device\" or \"wire\"; the transports it applies to (\"tcp\",\n"
         "\"serial\", \"can\", \"lpt\", in that order; none for a device fault); one_shot: it acts once\n"
         "when triggered, never for a duration or count.\"\"\"\n\n"
         "FAULT_CATALOGUE = (\n";
  for (std::size_t index = 0; index < faults::kFaultKindCount; ++index) {
    write_fault_row(out, faults::info(static_cast<faults::FaultKind>(index)));
  }
  out << ")\n";
  out.close();
  if (!out) {
    std::cerr << argv[0] << ": cannot write " << argv[1] << "\n";
    return 1;
  }
  return 0;
}
