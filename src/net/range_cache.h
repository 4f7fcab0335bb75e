// The on-disk cache of byte ranges fetched over HTTP: hierarchy chunks and nodes of octrees seen
// before come from the disk on the next visit, after one small request that checks the file has
// not changed on the server.
//
// Layout under the cache folder (by default $XDG_CACHE_HOME/parallax/http):
//   <16 hex digits: FNV-1a of the URL>/url         the URL, checked on load (hash collisions)
//   <...>/validator                                 ETag, Last-Modified and size it was fetched at
//   <...>/<offset>-<size>                           the bytes of one range
// Files are written under a temporary name and renamed, so a reader (this process or another)
// never sees half a range; a file that vanished or is short is a miss. A URL's ranges are kept
// only while its validator matches what the server says now (validate()); a URL whose server
// sends neither an ETag nor a Last-Modified is not cached, since its ranges could never be
// checked.
//
// Bounded: when the ranges exceed `budget_bytes`, the least recently used go (their files'
// modification times record the use, so the order survives between runs) until 90 % of the
// budget is left. Several processes may share a folder; each keeps its own count, so the bound
// holds per process, approximately for the folder.
//
// Thread-safe. Lookups (contains) touch no disk; read() and store() do I/O on the caller's thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/byte_source.h"

namespace parallax {

// What identifies the version of a file on a server.
struct CacheValidator {
  std::string etag;           // as sent, quotes and W/ included
  std::string last_modified;  // as sent
  std::uint64_t size = 0;
  // Ranges can be checked against a later answer only with an ETag or a Last-Modified.
  bool usable() const { return !etag.empty() || !last_modified.empty(); }
  // Same version: equal sizes and equal ETags, or with no ETag on either side, equal
  // Last-Modified.
  bool sameVersion(const CacheValidator& other) const;
};

struct RangeCacheStats {
  std::uint64_t hits = 0, misses = 0;
  std::uint64_t bytes_read = 0, bytes_stored = 0;
  std::uint64_t evicted_ranges = 0;
  std::uint64_t total_bytes = 0;  // of ranges on disk, as this process counts them
};

class RangeCache {
 public:
  // Creates `directory` when missing and scans it (sizes and times of every range). Throws
  // std::filesystem::filesystem_error when it cannot be created.
  RangeCache(std::filesystem::path directory, std::uint64_t budget_bytes);

  const std::filesystem::path& directory() const { return directory_; }
  std::uint64_t budget() const { return budget_; }

  // The validator the URL's ranges were fetched at; none when nothing is cached for it.
  std::optional<CacheValidator> validator(const std::string& url) const;
  // Records what the server says now. A validator that is not the stored one's version drops
  // every range of the URL; an unusable one (no ETag, no Last-Modified) also stops caching it.
  void validate(const std::string& url, const CacheValidator& now);

  // Whether [offset, offset + size) lies whole inside one cached range (no disk access).
  bool contains(const std::string& url, ByteRange range) const;
  // Copies the bytes at `offset` into `out` when one cached range holds them all; false on a miss
  // (nothing cached, or its file gone or short: the entry is then dropped).
  bool read(const std::string& url, std::uint64_t offset, std::span<std::byte> out);
  // Stores a range of a validated URL (ignored for a URL without a usable validator, and for
  // ranges larger than an eighth of the budget), then evicts down to the budget.
  void store(const std::string& url, std::uint64_t offset, std::span<const std::byte> bytes);

  RangeCacheStats stats() const;

 private:
  struct Entry {
    std::uint64_t size = 0;
    std::int64_t last_used_ns = 0;
  };
  struct UrlEntry {
    std::string url;
    std::optional<CacheValidator> validator;
    std::map<std::uint64_t, Entry> ranges;  // by offset
  };

  static std::string keyOf(const std::string& url);
  void scan();
  UrlEntry* find(const std::string& url);
  const UrlEntry* find(const std::string& url) const;
  // The entry holding [offset, offset + size), if any.
  static const std::pair<const std::uint64_t, Entry>* containing(const UrlEntry& entry,
                                                                 ByteRange range);
  void dropRanges(const std::string& key, UrlEntry& entry);
  void evictLocked();
  std::filesystem::path rangePath(const std::string& key, std::uint64_t offset,
                                  std::uint64_t size) const;

  std::filesystem::path directory_;
  std::uint64_t budget_ = 0;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, UrlEntry> urls_;  // by key (hash hex)
  std::uint64_t total_bytes_ = 0;
  std::uint64_t temp_counter_ = 0;
  mutable RangeCacheStats stats_;
};

}  // namespace parallax
