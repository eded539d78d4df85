// D4: the emulated flash kept in a file beside the scene (<scene>.flash) or named by --flash.
// save() writes a fresh temporary file (mkstemp), fsyncs it, renames it over the image and fsyncs
// the folder, so a crash never leaves half an image and a saved image survives a power cut.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "ldoem/control/flash_image.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::daemon {

class FileFlashStore final : public control::FlashStore {
 public:
  static constexpr std::size_t kMaxImageBytes = 1 << 20;

  // A symlink is resolved here (issue 27 D12): saves write through it to its target, and the link
  // stays a link. path() is the resolved path.
  explicit FileFlashStore(std::filesystem::path path);

  // The image; empty when the file does not exist yet (first power-up). A file that exists but
  // cannot be read (permissions, a folder, a FIFO, an I/O error) or is empty is an error naming
  // what was wrong: the daemon refuses to start on it rather than overwrite it (issue 11, 27).
  base::Expected<protocol::Bytes, std::string> read() const;
  // read(), with an unreadable file as empty (the FlashStore interface has no error channel).
  protocol::Bytes load() const override;
  // Removes the temporary files a save killed before its rename left beside the flash
  // (".NAME.XXXXXX", regular files only; issue 27 D13). Returns a line to log when it removed any.
  std::optional<std::string> remove_stale_temporaries() const;
  // On failure, the error names the flash file, the step and the OS error.
  Saved save(protocol::ByteView image) override;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace ldoem::daemon
