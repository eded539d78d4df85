// Typed errors of the PLY/PCD writers and readers. Callers branch on the value, never on text.
#pragma once

#include <cstdint>
#include <string_view>

#include "ldoem/base/expected.hpp"

namespace ldoem::cloud {

using base::Expected;
using base::Unexpected;

enum class CloudIoError : std::uint8_t {
  too_many_points,      // more points than a 32-bit count holds (PLY/PCD counts)
  bad_comment,          // a PLY comment with a line break would end the header early
  bad_magic,            // the file does not start like a PLY ("ply") or PCD (VERSION) file
  malformed_header,     // a header line out of order, unknown, or with wrong arguments
  unsupported_layout,   // valid in the format but not read here (big-endian PLY, lists, compressed PCD)
  missing_field,        // x, y or z absent
  inconsistent_header,  // counts disagree (FIELDS/SIZE/TYPE, POINTS != WIDTH*HEIGHT)
  truncated_data,       // fewer data bytes or values than the header announces
  malformed_number,     // an ASCII value that is not a number of the announced type
  cannot_open_file,     // the operating system refused to open the path
  io_failed,            // reading or writing the file failed part-way
};

[[nodiscard]] std::string_view to_string(CloudIoError error);

}  // namespace ldoem::cloud
