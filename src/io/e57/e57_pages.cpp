#include "io/e57/e57_pages.h"

#include <array>
#include <cstring>

#include "core/error.h"

namespace parallax {
namespace {

constexpr std::uint32_t kCastagnoliReflected = 0x82F63B78u;

std::array<std::uint32_t, 256> makeCrcTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (c >> 1) ^ kCastagnoliReflected : c >> 1;
    table[i] = c;
  }
  return table;
}

std::uint32_t crc32cTable(const unsigned char* p, std::size_t n) {
  static const std::array<std::uint32_t, 256> table = makeCrcTable();
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xFFu] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

#if defined(__x86_64__)
// The crc32 instruction computes exactly CRC-32C, but one chain of it waits 3 cycles an
// instruction: a page is checked as three interleaved streams of 336 bytes, joined by the linear
// map "336 zero bytes more" (crc(A B) = shift(crc(A)) ^ crc_from_zero(B)), tabulated once.
constexpr std::size_t kStreamWords = 42;  // 336 bytes; 3 streams take 1008 of a page's 1020

__attribute__((target("sse4.2"))) std::uint32_t crcWords(std::uint32_t crc, const unsigned char* p,
                                                         std::size_t words) {
  std::uint64_t c = crc;
  for (std::size_t i = 0; i < words; ++i) {
    std::uint64_t word;
    std::memcpy(&word, p + 8 * i, 8);
    c = __builtin_ia32_crc32di(c, word);
  }
  return std::uint32_t(c);
}

struct ShiftTable {
  std::uint32_t entry[4][256];
  ShiftTable() {
    static const unsigned char zeros[8 * kStreamWords] = {};
    for (int k = 0; k < 4; ++k) {
      for (std::uint32_t v = 0; v < 256; ++v)
        entry[k][v] = crcWords(v << (8 * k), zeros, kStreamWords);
    }
  }
  std::uint32_t shift(std::uint32_t crc) const {
    return entry[0][crc & 0xFF] ^ entry[1][(crc >> 8) & 0xFF] ^ entry[2][(crc >> 16) & 0xFF] ^
           entry[3][crc >> 24];
  }
};

__attribute__((target("sse4.2"))) std::uint32_t crc32cHardware(const unsigned char* p,
                                                               std::size_t n) {
  static const ShiftTable table;
  std::uint32_t crc = 0xFFFFFFFFu;
  std::size_t i = 0;
  constexpr std::size_t kStreamBytes = 8 * kStreamWords;
  for (; i + 3 * kStreamBytes <= n; i += 3 * kStreamBytes) {
    std::uint64_t a = crc, b = 0, c = 0;
    for (std::size_t w = 0; w < kStreamWords; ++w) {
      std::uint64_t wa, wb, wc;
      std::memcpy(&wa, p + i + 8 * w, 8);
      std::memcpy(&wb, p + i + kStreamBytes + 8 * w, 8);
      std::memcpy(&wc, p + i + 2 * kStreamBytes + 8 * w, 8);
      a = __builtin_ia32_crc32di(a, wa);
      b = __builtin_ia32_crc32di(b, wb);
      c = __builtin_ia32_crc32di(c, wc);
    }
    crc = table.shift(table.shift(std::uint32_t(a)) ^ std::uint32_t(b)) ^ std::uint32_t(c);
  }
  crc = crcWords(crc, p + i, (n - i) / 8);
  i += (n - i) / 8 * 8;
  for (; i < n; ++i) crc = __builtin_ia32_crc32qi(crc, p[i]);
  return crc ^ 0xFFFFFFFFu;
}
#endif

std::uint32_t loadBigEndian32(const std::byte* p) {
  return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 |
         std::uint32_t(p[3]);
}

void storeBigEndian32(std::byte* p, std::uint32_t v) {
  p[0] = std::byte(v >> 24), p[1] = std::byte(v >> 16), p[2] = std::byte(v >> 8),
  p[3] = std::byte(v);
}

std::string hex32(std::uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08X", v);
  return text;
}

constexpr std::size_t kVerifiedSlots = 64;
constexpr std::uint64_t kNotVerified = ~std::uint64_t{0};

}  // namespace

std::uint32_t crc32c(std::span<const std::byte> bytes) {
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
#if defined(__x86_64__)
  static const bool hardware = __builtin_cpu_supports("sse4.2");
  if (hardware) return crc32cHardware(p, bytes.size());
#endif
  return crc32cTable(p, bytes.size());
}

E57Pages::E57Pages(std::span<const std::byte> bytes, std::string name)
    : bytes_(bytes), name_(std::move(name)), verified_(kVerifiedSlots, kNotVerified) {
  if (bytes_.empty() || bytes_.size() % kE57PageSize != 0) {
    throw InputError({.file = name_,
                      .element = "E57 file",
                      .expected = "a length that is a whole number of 1024-byte pages",
                      .found = std::to_string(bytes_.size()) + " bytes",
                      .hint = "the file is truncated or not an E57 file"});
  }
}

void E57Pages::verifyPage(std::uint64_t page) const {
  std::uint64_t& slot = verified_[page % kVerifiedSlots];
  if (slot == page) return;
  const std::byte* start = bytes_.data() + page * kE57PageSize;
  const std::uint32_t computed = crc32c({start, kE57PageData});
  const std::uint32_t stored = loadBigEndian32(start + kE57PageData);
  if (computed != stored) {
    throw InputError({.file = name_,
                      .byte_offset = page * kE57PageSize,
                      .element = "page " + std::to_string(page),
                      .property = "CRC-32C checksum",
                      .expected = hex32(computed) + " (computed from the page's 1020 bytes)",
                      .found = hex32(stored),
                      .hint = "the file is damaged: this page was changed after it was written"});
  }
  slot = page;
}

void E57Pages::read(std::uint64_t logical, std::span<std::byte> out, const char* what) const {
  const std::uint64_t size = out.size();
  if (logical > logicalSize() || size > logicalSize() - logical) {
    throw InputError(
        {.file = name_,
         .byte_offset = e57LogicalToPhysical(logical),
         .element = what,
         .expected =
             "a range inside the file (" + std::to_string(logicalSize()) + " logical bytes)",
         .found = std::to_string(size) + " bytes from logical offset " + std::to_string(logical),
         .hint = "the file is truncated or an offset in it is wrong"});
  }
  std::uint64_t done = 0;
  while (done < size) {
    const std::uint64_t at = logical + done;
    const std::uint64_t page = at / kE57PageData;
    const std::uint64_t in_page = at % kE57PageData;
    const std::uint64_t n = std::min(kE57PageData - in_page, size - done);
    verifyPage(page);
    std::memcpy(out.data() + done, bytes_.data() + page * kE57PageSize + in_page, n);
    done += n;
  }
}

void E57PageWriter::flushPage() {
  storeBigEndian32(page_ + kE57PageData, crc32c({page_, kE57PageData}));
  if (written_pages_ == 0) first_page_.assign(page_, page_ + kE57PageData);
  file_.write(page_, kE57PageSize);
  ++written_pages_;
  fill_ = 0;
  std::memset(page_, 0, sizeof page_);
}

void E57PageWriter::write(std::span<const std::byte> bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t n = std::min<std::size_t>(kE57PageData - fill_, bytes.size() - done);
    std::memcpy(page_ + fill_, bytes.data() + done, n);
    fill_ += n, done += n;
    if (fill_ == kE57PageData) flushPage();
  }
}

void E57PageWriter::writeZeros(std::uint64_t count) {
  static const std::byte zeros[kE57PageData] = {};
  while (count > 0) {
    const std::uint64_t n = std::min<std::uint64_t>(count, kE57PageData);
    write({zeros, std::size_t(n)});
    count -= n;
  }
}

void E57PageWriter::finish() {
  if (fill_ > 0) flushPage();
}

void E57PageWriter::rewriteStart(std::span<const std::byte> bytes) {
  std::byte page[kE57PageSize] = {};
  std::memcpy(page, first_page_.data(), kE57PageData);
  std::memcpy(page, bytes.data(), std::min<std::size_t>(bytes.size(), kE57PageData));
  storeBigEndian32(page + kE57PageData, crc32c({page, kE57PageData}));
  file_.writeAt(0, page, kE57PageSize);
}

}  // namespace parallax
