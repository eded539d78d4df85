// ldoem-scan's output files: checked before the first request, written all or none.
// A scan takes tens of seconds of a device's time; a typo in an output folder must cost none of
// it, and a failure while writing must not leave a cloud without the preview the user asked for
// (or the reverse). So every path is checked first (its folder exists and takes a new file; the
// path is not a folder), then after the scan every file is encoded in memory, written to a
// temporary file beside its target, and only when all are written are they renamed into place.
// Messages carry the operating system's own words.
#pragma once

#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "ldoem/base/expected.hpp"

namespace ldoem::scan {

// Checks that PATH can be written: its folder exists, is a folder and accepts a new file (a
// temporary file is created there and removed again), and PATH itself is not a folder. The
// error names the path and the reason ("/nonexistent/x.ply: folder /nonexistent: No such file or
// directory").
[[nodiscard]] base::Expected<std::monostate, std::string> check_output_path(const std::filesystem::path& path);

struct OutputFile {
  std::filesystem::path path;
  std::string bytes;
};

// Writes every file to a temporary beside its target, flushes it, and renames all into place only
// when all were written; on any failure the temporaries are removed and no target changes. Returns
// the first error ("write scan.ply: No space left on device").
[[nodiscard]] base::Expected<std::monostate, std::string> write_all_or_none(const std::vector<OutputFile>& files);

}  // namespace ldoem::scan
