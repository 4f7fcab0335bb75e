#include "net/range_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace parallax {
namespace {

std::int64_t nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::int64_t mtimeNs(const struct stat& st) {
  return std::int64_t(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec;
}

// "<offset>-<size>"; nothing for any other name.
std::optional<ByteRange> parseRangeName(const std::string& name) {
  const std::size_t dash = name.find('-');
  if (dash == std::string::npos || dash == 0 || dash + 1 == name.size()) return std::nullopt;
  ByteRange range;
  const char* begin = name.data();
  auto [end, error] = std::from_chars(begin, begin + dash, range.offset);
  if (error != std::errc() || end != begin + dash) return std::nullopt;
  auto [end2, error2] = std::from_chars(begin + dash + 1, begin + name.size(), range.size);
  if (error2 != std::errc() || end2 != begin + name.size() || range.size == 0) return std::nullopt;
  return range;
}

std::string readSmallFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
bool writeAtomically(const std::filesystem::path& path, std::span<const std::byte> bytes,
                     std::uint64_t serial) {
  const std::filesystem::path temp =
      path.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(serial));
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += std::size_t(n);
  }
  const bool ok = ::close(fd) == 0 && done == bytes.size();
  if (!ok || std::rename(temp.c_str(), path.c_str()) != 0) {
    ::unlink(temp.c_str());
    return false;
  }
  return true;
}

std::string validatorText(const CacheValidator& v) {
  // One field a line; ETags and dates hold no newlines (the client drops such headers).
  return v.etag + "\n" + v.last_modified + "\n" + std::to_string(v.size) + "\n";
}

std::optional<CacheValidator> parseValidator(const std::string& text) {
  std::istringstream in(text);
  CacheValidator v;
  std::string size;
  if (!std::getline(in, v.etag) || !std::getline(in, v.last_modified) || !std::getline(in, size)) {
    return std::nullopt;
  }
  const auto [end, error] = std::from_chars(size.data(), size.data() + size.size(), v.size);
  if (error != std::errc() || end != size.data() + size.size()) return std::nullopt;
  return v;
}

}  // namespace

bool CacheValidator::sameVersion(const CacheValidator& other) const {
  if (size != other.size) return false;
  if (!etag.empty() || !other.etag.empty()) return etag == other.etag;
  return !last_modified.empty() && last_modified == other.last_modified;
}

RangeCache::RangeCache(std::filesystem::path directory, std::uint64_t budget_bytes)
    : directory_(std::move(directory)), budget_(budget_bytes) {
  std::filesystem::create_directories(directory_);
  scan();
}

std::string RangeCache::keyOf(const std::string& url) {
  // FNV-1a, 64 bits: the folder name; the stored URL settles collisions.
  std::uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : url) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::filesystem::path RangeCache::rangePath(const std::string& key, std::uint64_t offset,
                                            std::uint64_t size) const {
  return directory_ / key / (std::to_string(offset) + "-" + std::to_string(size));
}

void RangeCache::scan() {
  std::error_code error;
  const auto stale_before = nowNs() - std::int64_t(3600) * 1'000'000'000;
  for (const auto& dir : std::filesystem::directory_iterator(directory_, error)) {
    if (!dir.is_directory(error)) continue;
    const std::string key = dir.path().filename().string();
    const std::string url = readSmallFile(dir.path() / "url");
    if (url.empty() || keyOf(url) != key) continue;
    UrlEntry entry;
    entry.url = url;
    entry.validator = parseValidator(readSmallFile(dir.path() / "validator"));
    for (const auto& file : std::filesystem::directory_iterator(dir.path(), error)) {
      const std::string name = file.path().filename().string();
      struct stat st {};
      if (::stat(file.path().c_str(), &st) != 0) continue;
      if (name.starts_with(".tmp-")) {
        // Left by a process that died while writing (a live writer renames within moments).
        if (mtimeNs(st) < stale_before) ::unlink(file.path().c_str());
        continue;
      }
      const std::optional<ByteRange> range = parseRangeName(name);
      if (!range) continue;
      if (!entry.validator || std::uint64_t(st.st_size) != range->size) {
        ::unlink(file.path().c_str());  // unverifiable or damaged
        continue;
      }
      entry.ranges[range->offset] = {range->size, mtimeNs(st)};
      total_bytes_ += range->size;
    }
    urls_[key] = std::move(entry);
  }
  stats_.total_bytes = total_bytes_;
}

RangeCache::UrlEntry* RangeCache::find(const std::string& url) {
  const auto it = urls_.find(keyOf(url));
  return it == urls_.end() || it->second.url != url ? nullptr : &it->second;
}

const RangeCache::UrlEntry* RangeCache::find(const std::string& url) const {
  const auto it = urls_.find(keyOf(url));
  return it == urls_.end() || it->second.url != url ? nullptr : &it->second;
}

std::optional<CacheValidator> RangeCache::validator(const std::string& url) const {
  std::lock_guard lock(mutex_);
  const UrlEntry* entry = find(url);
  return entry ? entry->validator : std::nullopt;
}

void RangeCache::dropRanges(const std::string& key, UrlEntry& entry) {
  for (const auto& [offset, range] : entry.ranges) {
    ::unlink(rangePath(key, offset, range.size).c_str());
    total_bytes_ -= range.size;
  }
  entry.ranges.clear();
}

void RangeCache::validate(const std::string& url, const CacheValidator& now) {
  std::lock_guard lock(mutex_);
  const std::string key = keyOf(url);
  UrlEntry& entry = urls_[key];
  if (entry.url == url && entry.validator && now.usable() && entry.validator->sameVersion(now)) {
    return;
  }
  // A new URL in this slot (or a hash collision taking it over), or a new version.
  dropRanges(key, entry);
  entry.url = url;
  entry.validator.reset();
  std::error_code error;
  const std::filesystem::path dir = directory_ / key;
  std::filesystem::create_directories(dir, error);
  ::unlink((dir / "validator").c_str());
  if (error || !now.usable()) return;
  const std::string text = validatorText(now);
  const bool ok =
      writeAtomically(dir / "url", std::as_bytes(std::span(url)), ++temp_counter_) &&
      writeAtomically(dir / "validator", std::as_bytes(std::span(text)), ++temp_counter_);
  if (ok) entry.validator = now;
  stats_.total_bytes = total_bytes_;
}

const std::pair<const std::uint64_t, RangeCache::Entry>* RangeCache::containing(
    const UrlEntry& entry, ByteRange range) {
  auto it = entry.ranges.upper_bound(range.offset);
  if (it == entry.ranges.begin()) return nullptr;
  --it;
  if (it->first + it->second.size < range.end()) return nullptr;
  return &*it;
}

bool RangeCache::contains(const std::string& url, ByteRange range) const {
  std::lock_guard lock(mutex_);
  const UrlEntry* entry = find(url);
  return entry && entry->validator && containing(*entry, range) != nullptr;
}

bool RangeCache::read(const std::string& url, std::uint64_t offset, std::span<std::byte> out) {
  std::filesystem::path path;
  std::uint64_t start = 0;
  {
    std::lock_guard lock(mutex_);
    const UrlEntry* entry = find(url);
    const auto* hit =
        entry && entry->validator ? containing(*entry, {offset, out.size()}) : nullptr;
    if (!hit) {
      ++stats_.misses;
      return false;
    }
    path = rangePath(keyOf(url), hit->first, hit->second.size);
    start = hit->first;
  }
  bool ok = false;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd >= 0) {
    std::size_t done = 0;
    while (done < out.size()) {
      const ssize_t n =
          ::pread(fd, out.data() + done, out.size() - done, off_t(offset - start + done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += std::size_t(n);
    }
    ok = done == out.size();
    // The use, for the least-recently-used order of this and later runs.
    if (ok) ::futimens(fd, nullptr);
    ::close(fd);
  }
  std::lock_guard lock(mutex_);
  UrlEntry* entry = find(url);
  if (!ok) {
    ++stats_.misses;
    if (entry) {
      const auto it = entry->ranges.find(start);
      if (it != entry->ranges.end()) {
        ::unlink(path.c_str());
        total_bytes_ -= it->second.size;
        entry->ranges.erase(it);
      }
    }
    return false;
  }
  ++stats_.hits;
  stats_.bytes_read += out.size();
  if (entry) {
    const auto it = entry->ranges.find(start);
    if (it != entry->ranges.end()) it->second.last_used_ns = nowNs();
  }
  return true;
}

void RangeCache::store(const std::string& url, std::uint64_t offset,
                       std::span<const std::byte> bytes) {
  if (bytes.empty() || bytes.size() > budget_ / 8) return;
  std::uint64_t serial = 0;
  std::string key;
  {
    std::lock_guard lock(mutex_);
    const UrlEntry* entry = find(url);
    if (!entry || !entry->validator || containing(*entry, {offset, bytes.size()})) return;
    key = keyOf(url);
    serial = ++temp_counter_;
  }
  if (!writeAtomically(rangePath(key, offset, bytes.size()), bytes, serial)) return;
  std::lock_guard lock(mutex_);
  UrlEntry* entry = find(url);
  if (!entry || !entry->validator) {
    // Invalidated while the file was written: it must not outlive its version.
    ::unlink(rangePath(key, offset, bytes.size()).c_str());
    return;
  }
  auto [it, inserted] = entry->ranges.try_emplace(offset, Entry{bytes.size(), nowNs()});
  if (!inserted) {
    // A range at this offset of another size: the file names differ, keep the newer one only.
    if (it->second.size != bytes.size()) {
      ::unlink(rangePath(key, offset, it->second.size).c_str());
      total_bytes_ -= it->second.size;
      total_bytes_ += bytes.size();
    }
    it->second = {bytes.size(), nowNs()};
  } else {
    total_bytes_ += bytes.size();
  }
  stats_.bytes_stored += bytes.size();
  if (total_bytes_ > budget_) evictLocked();
  stats_.total_bytes = total_bytes_;
}

void RangeCache::evictLocked() {
  struct Candidate {
    std::int64_t last_used_ns;
    std::string key;
    std::uint64_t offset;
  };
  std::vector<Candidate> candidates;
  for (const auto& [key, entry] : urls_) {
    for (const auto& [offset, range] : entry.ranges) {
      candidates.push_back({range.last_used_ns, key, offset});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.last_used_ns != b.last_used_ns ? a.last_used_ns < b.last_used_ns
                                            : std::tie(a.key, a.offset) < std::tie(b.key, b.offset);
  });
  const std::uint64_t target = budget_ - budget_ / 10;
  for (const Candidate& c : candidates) {
    if (total_bytes_ <= target) break;
    UrlEntry& entry = urls_[c.key];
    const auto it = entry.ranges.find(c.offset);
    if (it == entry.ranges.end()) continue;
    ::unlink(rangePath(c.key, c.offset, it->second.size).c_str());
    total_bytes_ -= it->second.size;
    entry.ranges.erase(it);
    ++stats_.evicted_ranges;
  }
}

RangeCacheStats RangeCache::stats() const {
  std::lock_guard lock(mutex_);
  RangeCacheStats stats = stats_;
  stats.total_bytes = total_bytes_;
  return stats;
}

}  // namespace parallax
