#include "ldoem/endpoints/host_endpoint.hpp"

namespace ldoem::endpoints {

std::optional<OpenFailure> watch_readable(EndpointContext& context, int fd, io::EventLoop::FdCallback callback,
                                          io::RoundOrder order) {
  if (auto watched = context.loop.watch(fd, io::Interest::readable, std::move(callback), order); !watched) {
    return OpenFailure{false, watched.error().message()};
  }
  return std::nullopt;
}

}  // namespace ldoem::endpoints
