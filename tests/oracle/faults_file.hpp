// Every fault's case kept (numerics_sweep --faults-file): the report prints only the first ten
// faults, and a fault is fixed from its case's bytes, so the sweep appends one line per fault,
//   CASTER KIND HEX WHAT
// (caster embree or moving; kind wrong_object, range, missed or not_finite; HEX the case's bytes
// as `numerics_sweep --case` replays them; WHAT the judge's message), up to kMaxLines lines in
// the file (counting the lines already there): a run gone wrong fills no disk.
#pragma once

#include "differential.hpp"

#include <cstdint>
#include <fstream>
#include <string>

namespace ldoem::oracle {

class FaultsFile {
 public:
  static constexpr std::uint64_t kMaxLines = 10000;

  // Appends to `path`; ok() is false if it cannot be opened.
  explicit FaultsFile(const std::string& path);
  bool ok() const { return ok_; }
  // One line per fault of one case (`one` holds that case alone, case_faults filled).
  void add(const Stats& one, const std::string& case_hex);
  std::uint64_t written() const { return written_; }
  std::uint64_t dropped() const { return dropped_; }  // faults past the cap

 private:
  std::ofstream out_;
  bool ok_ = false;
  std::uint64_t lines_ = 0;  // in the file, those there before included
  std::uint64_t written_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace ldoem::oracle
