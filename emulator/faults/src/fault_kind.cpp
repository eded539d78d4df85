#include "ldoem/faults/fault_kind.hpp"

#include <array>
#include <string>

namespace ldoem::faults {
namespace {

#define LDOEM_FAULT_SET(...) {__VA_ARGS__}
#define LDOEM_FAULT_INFO(kind, class_, extent, transports, params)                                 \
  FaultKindInfo{FaultKind::kind, #kind, FaultClass::class_, TransportSet LDOEM_FAULT_SET transports, \
                FaultExtent::extent, FaultParamSet LDOEM_FAULT_SET params},

// Indexed by FaultKind: both are expanded from the same list in the same order. The names the
// list's columns use are in scope in this function only (a unity build puts other files of the
// library in this one's scope).
constexpr std::array<FaultKindInfo, kFaultKindCount> expand_fault_catalogue() {
  using enum protocol::Transport;
  using enum FaultParam;
  return {{LDOEM_FAULT_CATALOGUE(LDOEM_FAULT_INFO)}};
}
constexpr std::array<FaultKindInfo, kFaultKindCount> kCatalogue = expand_fault_catalogue();

#undef LDOEM_FAULT_INFO
#undef LDOEM_FAULT_SET

}  // namespace

const FaultKindInfo& info(FaultKind kind) { return kCatalogue.at(static_cast<std::size_t>(kind)); }

std::string_view fault_name(FaultKind kind) { return info(kind).name; }

std::optional<FaultKind> fault_kind_from_name(std::string_view name) {
  for (const FaultKindInfo& entry : kCatalogue) {
    if (entry.name == name) return entry.kind;
  }
  return std::nullopt;
}

bool applies_to(FaultKind kind, Transport transport) { return info(kind).transports.contains(transport); }

bool accepts(FaultKind kind, FaultParam param) { return info(kind).params.contains(param); }

std::string_view all_fault_names() {
  // Built once from the catalogue (a function-local static: thread-safe, and only a daemon that
  // reports an unknown kind pays for it).
  static const std::string names = [] {
    std::string joined;
    for (const FaultKindInfo& entry : kCatalogue) {
      if (!joined.empty()) joined += ", ";
      joined += entry.name;
    }
    return joined;
  }();
  return names;
}

}  // namespace ldoem::faults
