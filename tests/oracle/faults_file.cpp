#include "faults_file.hpp"

#include <algorithm>
#include <iterator>

namespace ldoem::oracle {

FaultsFile::FaultsFile(const std::string& path) {
  {
    std::ifstream existing(path);
    lines_ = static_cast<std::uint64_t>(
        std::count(std::istreambuf_iterator<char>(existing), std::istreambuf_iterator<char>(), '\n'));
  }
  out_.open(path, std::ios::app);
  ok_ = out_.good();
}

void FaultsFile::add(const Stats& one, const std::string& case_hex) {
  for (const std::string& fault : one.case_faults) {
    if (lines_ >= kMaxLines) {
      ++dropped_;
      continue;
    }
    // "moving range: skipped ..." -> "moving range HEX skipped ..."
    const std::size_t colon = fault.find(": ");
    const std::string tag = fault.substr(0, colon);
    const std::string what = colon == std::string::npos ? std::string() : fault.substr(colon + 2);
    out_ << tag << ' ' << case_hex << ' ' << what << '\n';
    ++lines_;
    ++written_;
  }
  out_.flush();  // a sweep stopped midway keeps what it found
}

}  // namespace ldoem::oracle
