// A fresh folder under /tmp for one test, removed with everything in it at the end, and the
// files a test writes into it (scene files, configurations) or reads back.
#pragma once

#include <filesystem>
#include <string>

namespace ldoem::test_support {

class TempDir {
 public:
  // Throws std::runtime_error when no folder can be made: GoogleTest reports it as a failure.
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& folder() const { return folder_; }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  // Writes `text` to path(name) and returns that path.
  std::string write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path folder_;
};

// The whole content of a file (empty when it cannot be read).
std::string read_file(const std::string& path);

}  // namespace ldoem::test_support
