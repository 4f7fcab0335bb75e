// The bytes the COPC reader reads, a range at a time: a local file (pread) or bytes in memory
// (tests, fuzzing). A reader asks for ranges and never learns which it has.
//
// The one call, read(offset, out, element), is core/byte_source.h's ByteSource::read(offset,
// out, ReadContext{.element = element}) with another name; adaptByteSource() reads a ByteSource
// (an http(s) URL's, net/network.h) through it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <stop_token>
#include <string>
#include <string_view>
#include <vector>

#include "core/byte_source.h"

namespace parallax {

class CopcRangeSource {
 public:
  virtual ~CopcRangeSource() = default;
  // The path, as messages name it.
  virtual const std::string& name() const = 0;
  virtual std::uint64_t size() const = 0;
  // Reads out.size() bytes at `offset`. Thread-safe. A range past size(), or a failed read, is
  // an InputError naming the file, the offset and `element` ("hierarchy page at byte 1234").
  virtual void read(std::uint64_t offset, std::span<std::byte> out,
                    std::string_view element) const = 0;
  // read(), given up with ReadCancelled (core/byte_source.h) when `cancel` is requested before
  // the bytes arrive. Default: read(), never cancelled (local sources are quick).
  virtual void readCancellable(std::uint64_t offset, std::span<std::byte> out,
                               std::string_view element, std::stop_token cancel) const {
    (void)cancel;
    read(offset, out, element);
  }
  // False when a read may wait on a network (the reader then keeps page reads off the frame
  // loop and hints what it will read; core/byte_source.h).
  virtual bool local() const { return true; }
  // The ranges that will be read soon, most urgent first (ByteSource::prefetch). Never waits.
  virtual void prefetch(std::span<const ByteRange> ranges) const { (void)ranges; }
};

// Throws InputError (the path, why) when the file cannot be opened.
std::unique_ptr<CopcRangeSource> openCopcFileSource(const std::filesystem::path& path);
// Reads through a ByteSource (a URL's, or any other).
std::unique_ptr<CopcRangeSource> adaptByteSource(std::unique_ptr<ByteSource> source);
std::unique_ptr<CopcRangeSource> makeCopcMemorySource(std::vector<std::byte> bytes,
                                                      std::string name);

}  // namespace parallax
