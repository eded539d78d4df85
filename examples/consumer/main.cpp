// ldoem-consumer ENDPOINT: connects to a scanner (or ldoem-emud) through libldoem, prints its
// identification and status, spins the head up, takes one profile and prints how many points
// it has. Exit status 0 when all of that worked, 1 otherwise.
#include <chrono>
#include <iostream>

#include "ldoem/driver/endpoint.hpp"
#include "ldoem/driver/error.hpp"
#include "ldoem/driver/scanner.hpp"
#include "ldoem/driver/transport.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: ldoem-consumer ENDPOINT   (e.g. tcp:127.0.0.1:49152 or can:vcan0)\n";
    return 2;
  }
  auto endpoint = ldoem::driver::parse_endpoint(argv[1]);
  if (!endpoint) {
    std::cerr << "ldoem-consumer: " << argv[1] << ": " << endpoint.error().detail << "\n";
    return 2;
  }
  auto transport = ldoem::driver::open_transport(*endpoint);
  if (!transport) {
    std::cerr << "ldoem-consumer: " << ldoem::driver::describe(transport.error()) << "\n";
    return 1;
  }
  ldoem::driver::Scanner scanner(std::move(transport.value()));
  const auto fail = [](const ldoem::driver::DriverError& error) {
    std::cerr << "ldoem-consumer: " << ldoem::driver::describe(error) << "\n";
    return 1;
  };
  if (auto status = scanner.connect(); !status) return fail(status.error());
  auto identification = scanner.identify_all();
  if (!identification) return fail(identification.error());
  for (const auto& entry : *identification) std::cout << "ident " << entry.item << ": " << entry.text << "\n";
  if (auto rotating = scanner.trans_rotate(); !rotating) return fail(rotating.error());
  if (auto measuring = scanner.trans_measure(); !measuring) return fail(measuring.error());
  if (auto asked = scanner.get_profile(1, ldoem::protocol::kFormatRangeEcho); !asked) return fail(asked.error());
  auto profile = scanner.next_profile(ldoem::driver::Clock::now() + std::chrono::seconds(5));
  if (!profile) return fail(profile.error());
  std::size_t points = 0;
  for (const auto& sector : profile->sectors) points += sector.points.size();
  std::cout << "profile " << profile->profile_count << ": " << points << " points\n";
  // MEASURE -> ROTATE -> IDLE: the way back that the state table allows (spec 5).
  if (auto rotating = scanner.trans_rotate(); !rotating) return fail(rotating.error());
  if (auto idle = scanner.trans_idle(); !idle) return fail(idle.error());
  return 0;
}
