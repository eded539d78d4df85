// Reads edges on named GPIO lines with libgpiod 1.6 (v1 uAPI): the gpio back end of the
// pseudo-LPT (D8), where the lines DIR, CLK and MODE of a gpio-sim chip stand for DATA0..2.
// It reports edges with the kernel's timestamps; what an edge means is the drive board's job.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/io/io_error.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace ldoem::io {

enum class Edge { rising, falling };

struct GpioEdgeEvent {
  std::size_t line_index = 0;  // position of the line in the names given to open()
  Edge edge = Edge::rising;
  // Kernel timestamp of the edge on CLOCK_MONOTONIC (the v1 uAPI's clock since Linux 5.7),
  // the same clock as EventLoop::now().
  std::chrono::nanoseconds timestamp{0};
};

class GpioLineReader {
 public:
  // `chip`: a path (/dev/gpiochip0), a chip name (gpiochip0) or a chip label (ldoem-lpt).
  // Requests both-edge events on every line in `line_names` (found by name on that chip) for
  // `consumer`; each line's event descriptor is non-blocking.
  static IoResult<GpioLineReader> open(std::string_view chip,
                                       const std::vector<std::string>& line_names,
                                       std::string_view consumer = "ldoem-emud");

  GpioLineReader(GpioLineReader&&) noexcept;
  GpioLineReader& operator=(GpioLineReader&&) noexcept;
  ~GpioLineReader();

  // One descriptor per line (the v1 uAPI has no combined one): watch each with the EventLoop,
  // and call read_events() when any is readable.
  std::vector<int> event_fds() const;
  // Every edge waiting on any line, oldest first by kernel timestamp (so DIR set just before a
  // CLK edge is seen before it). Empty when none are waiting.
  IoResult<std::vector<GpioEdgeEvent>> read_events();
  // Current level of every line (0 or 1), in the order of the names: the state before any edge.
  IoResult<std::vector<int>> levels();

  const std::string& chip_name() const { return chip_name_; }
  const std::vector<std::string>& line_names() const { return line_names_; }

 private:
  struct ChipCloser {
    void operator()(gpiod_chip* chip) const;
  };
  GpioLineReader(std::unique_ptr<gpiod_chip, ChipCloser> chip, std::string chip_name,
                 std::vector<std::string> line_names, std::vector<gpiod_line*> lines);

  std::unique_ptr<gpiod_chip, ChipCloser> chip_;  // closing the chip releases its lines
  std::string chip_name_;
  std::vector<std::string> line_names_;
  std::vector<gpiod_line*> lines_;  // owned by chip_
};

}  // namespace ldoem::io
