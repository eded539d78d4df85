#include "mesh_precount.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <functional>
#include <string_view>

namespace ldoem::scene::detail {
namespace {

constexpr std::uintmax_t kStlHeaderBytes = 84;  // 80 bytes of text, then the triangle count
constexpr std::uintmax_t kStlTriangleBytes = 50;

bool read_at(int fd, std::uintmax_t offset, char* out, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t got = ::pread(fd, out + done, size - done, static_cast<off_t>(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    done += static_cast<std::size_t>(got);
  }
  return true;
}

// Calls on_line(first word, number of words) for every line of the file, in one pass with a
// fixed buffer (only the first word is kept, up to 15 characters).
bool for_each_line(int fd, const std::function<void(std::string_view, std::size_t)>& on_line) {
  std::array<char, 65536> buffer{};
  std::string first;
  std::size_t words = 0;
  bool in_word = false;
  std::uintmax_t offset = 0;
  for (;;) {
    const ssize_t got = ::pread(fd, buffer.data(), buffer.size(), static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return false;
    if (got == 0) break;
    offset += static_cast<std::uintmax_t>(got);
    for (ssize_t i = 0; i < got; ++i) {
      const char c = buffer[static_cast<std::size_t>(i)];
      if (c == '\n' || c == '\r') {
        if (words > 0) on_line(first, words);
        first.clear();
        words = 0;
        in_word = false;
      } else if (c == ' ' || c == '\t') {
        in_word = false;
      } else {
        if (!in_word) ++words;
        in_word = true;
        if (words == 1 && first.size() < 15) first.push_back(c);
      }
    }
  }
  if (words > 0) on_line(first, words);
  return true;
}

MeshCountResult count_stl(int fd, std::uintmax_t bytes) {
  std::array<char, kStlHeaderBytes> header{};
  if (bytes >= kStlHeaderBytes && read_at(fd, 0, header.data(), header.size())) {
    std::uint32_t claimed = 0;
    std::memcpy(&claimed, header.data() + 80, sizeof claimed);  // little-endian on every target we build
    const bool text = std::string_view(header.data(), 5) == "solid";
    if (bytes == kStlHeaderBytes + kStlTriangleBytes * claimed) return {MeshCount{claimed, 3u * claimed}, {}};
    if (!text) {
      return {{}, "binary STL header says " + std::to_string(claimed) + " triangles, but the file has room for " +
                      std::to_string((bytes - kStlHeaderBytes) / kStlTriangleBytes)};
    }
  }
  MeshCount count;
  if (!for_each_line(fd, [&](std::string_view word, std::size_t) {
        if (word == "facet") ++count.triangles;
      })) {
    return {{}, std::string("cannot read: ") + std::strerror(errno)};
  }
  count.vertices = 3 * count.triangles;
  return {count, {}};
}

MeshCountResult count_obj(int fd) {
  MeshCount count;
  if (!for_each_line(fd, [&](std::string_view word, std::size_t words) {
        if (word == "v") ++count.vertices;
        if (word == "f" && words >= 4) count.triangles += words - 3;  // "f a b c d": 2 triangles
      })) {
    return {{}, std::string("cannot read: ") + std::strerror(errno)};
  }
  return {count, {}};
}

// PLY: the header's `element vertex N` and `element face N`; every element takes at least one
// byte per property in the file, so counts beyond the file's size are a lie.
MeshCountResult count_ply(int fd, std::uintmax_t bytes) {
  std::array<char, 4096> header{};
  const std::size_t size = static_cast<std::size_t>(std::min<std::uintmax_t>(bytes, header.size()));
  if (!read_at(fd, 0, header.data(), size)) return {{}, std::string("cannot read: ") + std::strerror(errno)};
  const std::string_view text(header.data(), size);
  MeshCount count;
  const auto element = [&](std::string_view name) -> std::optional<std::uintmax_t> {
    const std::string key = "element " + std::string(name) + " ";
    const auto at = text.find(key);
    if (at == std::string_view::npos) return std::uintmax_t{0};
    std::uintmax_t value = 0;
    for (std::size_t i = at + key.size(); i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) {
      if (value > bytes) return std::nullopt;
      value = value * 10 + static_cast<std::uintmax_t>(text[i] - '0');
    }
    return value;
  };
  const auto vertices = element("vertex");
  const auto faces = element("face");
  if (!vertices || !faces || *vertices > bytes || *faces > bytes) {
    return {{}, "PLY header counts more elements than the file has bytes"};
  }
  count.vertices = static_cast<std::size_t>(*vertices);
  count.triangles = static_cast<std::size_t>(*faces);  // a polygon face counts once here (a lower bound)
  return {count, {}};
}

}  // namespace

MeshCountResult precount_mesh(int fd, std::uintmax_t bytes, const std::string& extension) {
  if (extension == ".stl") return count_stl(fd, bytes);
  if (extension == ".obj") return count_obj(fd);
  if (extension == ".ply") return count_ply(fd, bytes);
  return {};
}

}  // namespace ldoem::scene::detail
