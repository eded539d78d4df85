#include "listen_socket.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <memory>
#include <string>

namespace ldoem::hub {

using driver::fail;
using driver::system_error;

driver::Expected<ListeningSocket, driver::DriverError> open_listening_socket(const ListenAddress& address) {
  const std::string object = address.host + ":" + std::to_string(address.port);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(address.port);
  if (const int status = ::getaddrinfo(address.host.c_str(), port.c_str(), &hints, &found); status != 0) {
    return fail(driver::make_error(driver::ErrorKind::invalid_argument, "resolve", object, ::gai_strerror(status)));
  }
  std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> addresses(found, &::freeaddrinfo);
  const int fd = ::socket(found->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    return fail(system_error("socket", object, errno));
  }
  const auto failed = [fd, &object](const char* operation) {
    const int error = errno;
    ::close(fd);
    return fail(system_error(operation, object, error));
  };
  const int yes = 1;
  (void)::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  if (::bind(fd, found->ai_addr, found->ai_addrlen) != 0) {
    return failed("bind");
  }
  // The system's largest backlog: a connect flood must not make new clients wait for a SYN retry.
  if (::listen(fd, SOMAXCONN) != 0) {
    return failed("listen");
  }
  sockaddr_storage bound{};
  socklen_t length = sizeof bound;
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &length) != 0) {
    return failed("getsockname");
  }
  const std::uint16_t bound_port = bound.ss_family == AF_INET6
                                       ? ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port)
                                       : ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
  return ListeningSocket{fd, bound_port};
}

}  // namespace ldoem::hub
