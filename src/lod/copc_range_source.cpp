#include "lod/copc_range_source.h"

#include <optional>

#include "core/error.h"
#include "io/range_reader.h"

namespace parallax {
namespace {

// Over io's RangeReader (pread, or memory), adding the element to its errors.
class RangeReaderSource final : public CopcRangeSource {
 public:
  explicit RangeReaderSource(const std::filesystem::path& path) : reader_(path) {}
  RangeReaderSource(std::vector<std::byte> bytes, std::string name)
      : bytes_(std::move(bytes)), reader_(std::span<const std::byte>(bytes_), std::move(name)) {}

  const std::string& name() const override { return reader_.name(); }
  std::uint64_t size() const override { return reader_.size(); }
  void read(std::uint64_t offset, std::span<std::byte> out,
            std::string_view element) const override {
    if (offset > reader_.size() || out.size() > reader_.size() - offset) {
      throw InputError({.file = reader_.name(),
                        .byte_offset = offset,
                        .element = std::string(element),
                        .expected = std::to_string(out.size()) + " bytes inside the file (" +
                                    std::to_string(reader_.size()) + " bytes)",
                        .found = "a range that ends past it",
                        .hint = "the file is truncated, or its COPC hierarchy is damaged"});
    }
    try {
      reader_.read(offset, out.size(), out.data());
    } catch (const InputError& e) {
      InputErrorInfo info = e.info();
      if (info.element.empty()) info.element = std::string(element);
      throw InputError(std::move(info));
    }
  }

 private:
  std::vector<std::byte> bytes_;  // memory sources own their bytes (before reader_)
  RangeReader reader_;
};

class ByteSourceAdapter final : public CopcRangeSource {
 public:
  explicit ByteSourceAdapter(std::unique_ptr<ByteSource> source) : source_(std::move(source)) {}
  const std::string& name() const override { return source_->name(); }
  std::uint64_t size() const override { return source_->size(); }
  void read(std::uint64_t offset, std::span<std::byte> out,
            std::string_view element) const override {
    source_->read(offset, out, ReadContext{.element = element});
  }
  void readCancellable(std::uint64_t offset, std::span<std::byte> out, std::string_view element,
                       std::stop_token cancel) const override {
    source_->read(offset, out, ReadContext{.cancel = std::move(cancel), .element = element});
  }
  bool local() const override { return source_->local(); }
  void prefetch(std::span<const ByteRange> ranges) const override { source_->prefetch(ranges); }

 private:
  std::unique_ptr<ByteSource> source_;
};

}  // namespace

std::unique_ptr<CopcRangeSource> adaptByteSource(std::unique_ptr<ByteSource> source) {
  return std::make_unique<ByteSourceAdapter>(std::move(source));
}

std::unique_ptr<CopcRangeSource> openCopcFileSource(const std::filesystem::path& path) {
  return std::make_unique<RangeReaderSource>(path);
}

std::unique_ptr<CopcRangeSource> makeCopcMemorySource(std::vector<std::byte> bytes,
                                                      std::string name) {
  return std::make_unique<RangeReaderSource>(std::move(bytes), std::move(name));
}

}  // namespace parallax
