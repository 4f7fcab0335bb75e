// libFuzzer target for the HTTP range cache's files on disk (net/range_cache.h): a cache folder
// left by another process, a crash or another version may hold anything. Whatever it holds,
// opening the cache and using it must give a miss or bytes that a range file holds at that place,
// never a crash: a range is served only from a file named as the cache names ranges and exactly
// as long as its name says, and after a new version a range stored reads back as stored.
//
// Input framing, parts separated by NUL bytes: the URL; the `validator` file's bytes; then pairs
// of a range file's name and its bytes (at most 8). The URL's folder is named as the cache names
// it (FNV-1a of the URL, 16 hex digits; the layout range_cache.h documents), so the contents are
// what gets tested, not the hash. Seeds in fuzz/corpus/range_cache/ are folders as Parallax
// writes them, framed this way.
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "net/range_cache.h"

namespace {

std::string folderOf(std::string_view url) {
  std::uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : url) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

void writeFile(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

// "<offset>-<size>" as the cache reads it; none for any other name.
std::optional<std::pair<std::uint64_t, std::uint64_t>> rangeOfName(std::string_view name) {
  const std::size_t dash = name.find('-');
  if (dash == std::string_view::npos) return std::nullopt;
  std::uint64_t offset = 0, size = 0;
  const auto a = std::from_chars(name.data(), name.data() + dash, offset);
  const auto b = std::from_chars(name.data() + dash + 1, name.data() + name.size(), size);
  if (a.ec != std::errc() || a.ptr != name.data() + dash || b.ec != std::errc() ||
      b.ptr != name.data() + name.size() || dash == 0 || size == 0) {
    return std::nullopt;
  }
  return std::pair{offset, size};
}

const std::filesystem::path& workFolder() {
  static const std::filesystem::path folder = [] {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "parallax-fuzz-range-cache.XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) std::abort();
    return std::filesystem::path(pattern);
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  std::vector<std::string_view> parts;
  for (std::size_t begin = 0; begin <= input.size() && parts.size() < 18;) {
    const std::size_t end = std::min(input.find('\0', begin), input.size());
    parts.push_back(input.substr(begin, end - begin));
    begin = end + 1;
  }
  if (parts.size() < 2 || parts[0].empty()) return 0;
  const std::string url(parts[0]);

  const std::filesystem::path root = workFolder();
  std::filesystem::remove_all(root);
  const std::filesystem::path folder = root / folderOf(url);
  std::filesystem::create_directories(folder);
  writeFile(folder / "url", url);
  writeFile(folder / "validator", parts[1]);
  // The range files the cache may serve from: named as it names them ("<offset>-<size>" in
  // decimal, no leading zeros), the last bytes written under each name.
  struct Planted {
    std::uint64_t offset, size;
    std::string bytes;
  };
  std::vector<Planted> planted;
  for (std::size_t i = 2; i + 1 < parts.size(); i += 2) {
    const std::string name(parts[i]);
    if (name.empty() || name == "url" || name == "validator" || name == "." || name == ".." ||
        name.find('/') != std::string::npos) {
      continue;
    }
    writeFile(folder / name, parts[i + 1]);
    const auto range = rangeOfName(name);
    if (!range || std::to_string(range->first) + "-" + std::to_string(range->second) != name) {
      continue;
    }
    std::erase_if(planted, [&](const Planted& p) {
      return p.offset == range->first && p.size == range->second;
    });
    planted.push_back({range->first, range->second, std::string(parts[i + 1])});
  }
  // Whether `out`, read at `offset`, is what some whole planted range holds there.
  const auto heldByAFile = [&](std::uint64_t offset, std::span<const std::byte> out) {
    return std::any_of(planted.begin(), planted.end(), [&](const Planted& p) {
      return p.bytes.size() == p.size && p.offset <= offset && p.size >= out.size() &&
             offset - p.offset <= p.size - out.size() &&
             std::memcmp(out.data(), p.bytes.data() + (offset - p.offset), out.size()) == 0;
    });
  };

  parallax::RangeCache cache(root, 1 << 20);
  const std::optional<parallax::CacheValidator> validator = cache.validator(url);
  for (const Planted& p : planted) {
    if (p.size > (1u << 16)) continue;
    std::vector<std::byte> out(p.size);
    if (cache.read(url, p.offset, out)) {
      if (!validator || !heldByAFile(p.offset, out)) __builtin_trap();
    }
  }

  // The server says the file changed: every old range goes, and a range stored reads back.
  parallax::CacheValidator now = validator.value_or(parallax::CacheValidator{});
  now.etag += "\"changed\"";
  cache.validate(url, now);
  const std::string_view stored = parts.back().substr(0, 4096);
  if (!stored.empty()) {
    cache.store(url, 7, std::as_bytes(std::span(stored)));
    std::vector<std::byte> out(stored.size());
    if (!cache.read(url, 7, out)) __builtin_trap();
    if (std::memcmp(out.data(), stored.data(), stored.size()) != 0) __builtin_trap();
  }
  return 0;
}
