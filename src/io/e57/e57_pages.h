// The physical layer of an E57 file (ASTM E2807 section 8): the file is a sequence of pages of
// 1024 bytes, each 1020 bytes of data followed by the CRC-32C of those bytes (stored big endian).
// Every offset inside the file's sections is "logical" (counting data bytes only) or "physical"
// (counting the checksums too); the header and the XML name physical offsets, section contents
// are read through logical ones.
//
// E57Pages reads logical ranges from the bytes of a whole file (mapped or in memory), checking
// the checksum of every page it touches once; E57PageWriter writes a file page by page.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/point_file.h"

namespace parallax {

inline constexpr std::uint64_t kE57PageSize = 1024;
inline constexpr std::uint64_t kE57PageData = 1020;
// The file header (ASTM E2807): the signature, the version, the file's physical length, the
// XML section's offset and length, and the page size. The reader and the writer share it.
inline constexpr char kE57Signature[8] = {'A', 'S', 'T', 'M', '-', 'E', '5', '7'};
inline constexpr std::size_t kE57FileHeaderSize = 48;

// CRC-32C (Castagnoli, reflected, initial and final xor 0xFFFFFFFF) of `bytes`. Uses the SSE 4.2
// instruction where the CPU has it, a table otherwise.
std::uint32_t crc32c(std::span<const std::byte> bytes);

inline std::uint64_t e57LogicalToPhysical(std::uint64_t logical) {
  return logical / kE57PageData * kE57PageSize + logical % kE57PageData;
}
// The logical offset of a physical one; a physical offset inside a checksum has none (the
// caller checks `physical % kE57PageSize < kE57PageData`).
inline std::uint64_t e57PhysicalToLogical(std::uint64_t physical) {
  return physical / kE57PageSize * kE57PageData + physical % kE57PageSize;
}

class E57Pages {
 public:
  // `bytes` is the whole file and must outlive this object; `name` stands for it in messages.
  // The length must be a whole number of pages (an InputError otherwise, naming the length).
  E57Pages(std::span<const std::byte> bytes, std::string name);

  const std::string& name() const { return name_; }
  std::uint64_t physicalSize() const { return bytes_.size(); }
  std::uint64_t logicalSize() const { return bytes_.size() / kE57PageSize * kE57PageData; }

  // Copies logical bytes [logical, logical + out.size()) into `out`, checking each page's CRC
  // (InputError naming the page's physical offset, the stored and the computed checksum), and
  // that the range lies in the file (InputError naming `what`, the range and the file's length).
  void read(std::uint64_t logical, std::span<std::byte> out, const char* what) const;

 private:
  void verifyPage(std::uint64_t page) const;

  std::span<const std::byte> bytes_;
  std::string name_;
  // Pages already verified, by page number modulo the size: a direct-mapped cache, so reading
  // a packet that shares a page with the last one does not check that page again.
  mutable std::vector<std::uint64_t> verified_;
};

// Writes an E57 file's pages: bytes go into the current page and each full page leaves with its
// checksum. The first page can be rewritten at the end (the file header holds offsets known only
// then) by writeHeaderPage().
class E57PageWriter {
 public:
  explicit E57PageWriter(OutputFile& file) : file_(file) {}

  std::uint64_t logicalPosition() const { return written_pages_ * kE57PageData + fill_; }
  std::uint64_t physicalPosition() const { return e57LogicalToPhysical(logicalPosition()); }
  void write(std::span<const std::byte> bytes);
  void writeZeros(std::uint64_t count);
  // Pads the last page with zeros and writes it; afterwards the file is a whole number of pages.
  void finish();
  // Overwrites the first bytes of page 0 (the file header, whose offsets are known only at the
  // end) and that page's checksum. Only after finish().
  void rewriteStart(std::span<const std::byte> bytes);

 private:
  void flushPage();

  OutputFile& file_;
  std::byte page_[kE57PageSize] = {};
  std::uint64_t fill_ = 0;
  std::uint64_t written_pages_ = 0;
  std::vector<std::byte> first_page_;  // page 0's data as written, for rewriteStart
};

}  // namespace parallax
