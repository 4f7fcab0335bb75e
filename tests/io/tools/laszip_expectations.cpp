// Prints the values tests/io/test_laz_layered.cpp expects from LASzip, computed by LASzip itself
// through its public C API (laszip_api.h), so that the test's tables can be checked and
// regenerated from the repository.
//
// It is not built by the project or by CI: LASzip is not a Debian package. Build LASzip 3.5.1
// from its public source (github.com/LASzip/LASzip, with cmake) outside the repository; with
// LZ=<its source tree> and LB=<its cmake build folder>, from the repository root (one command):
//
//   g++ -std=c++20 -O2 -Isrc -I$LZ/dll -I$LZ/include/laszip -I$LB/include/laszip
//       tests/io/tools/laszip_expectations.cpp -L$LB/lib -llaszip -Wl,-rpath,$LB/lib
//       -o /tmp/laszip_expectations
//
// Run it with the folder holding laz/ (PARALLAX_TEST_DATA, ../shared/data by default) and a
// scratch folder for its LAS and LAZ files. It prints, inside a dummy function so that
// clang-format lays the lines out as the test has them, the expectFileDecodesAsLaszip(...) calls
// of DecodesSimpleCopcAsLaszip and DecodesEllipsoidCopcAsLaszip and the `cases` table of
// EncoderWritesLaszipBytes. To check the test's values (no output: equal), or to regenerate them
// (paste the lines printed), one command:
//
//   diff <(/tmp/laszip_expectations ../shared/data /tmp/laszip_scratch |
//          clang-format --assume-filename=x.cpp | sed '1d;$d')
//        <(awk '/^  expectFileDecodesAsLaszip\(/,/^      }\);/;
//               /^  const LaszipOutput cases\[\] = \{/,/^  };/' tests/io/test_laz_layered.cpp)
//
// What it computes:
//   - decoding: each real file is read with laszip_open_reader + laszip_read_point; each
//     laszip_point is written back as its raw LAS 1.4 record (the extended_* fields give the
//     return, channel, classification and scan angle bytes); printed are the point count, the
//     number of chunks (from the file's chunk table), FNV-1a 64 over all records and a few records
//     in hex.
//   - encoding: the records of makeSyntheticRecords() (the test's own generator,
//     tests/io/laz_synthetic_points.h, included here so that the inputs are the same) are written
//     to an uncompressed LAS file (LAS 1.4 for item version 3; LAS 1.5 for version 4, which makes
//     LASzip pick version 4), read by laszip_open_reader and written by laszip_open_writer after
//     laszip_request_native_extension(TRUE) and laszip_set_chunk_size(chunk). Printed are the size
//     and FNV-1a 64 of the file's chunks (from the point data offset + 8 to the chunk table). The
//     tool checks that LASzip wrote the item versions and chunk size asked for and that LASzip
//     decodes its file back to exactly the input records, and fails otherwise.
#include <laszip_api.h>

#include <cinttypes>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "../laz_synthetic_points.h"

namespace {

using parallax::laz::testing::makeSyntheticRecords;
using parallax::laz::testing::syntheticRecordLength;
using parallax::laz::testing::SyntheticSpec;

std::uint64_t fnv1a64(const std::vector<std::uint8_t>& bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (std::uint8_t b : bytes) {
    hash ^= b;
    hash *= 0x100000001b3ull;
  }
  return hash;
}

std::string hex(const std::uint8_t* bytes, std::size_t size) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (std::size_t i = 0; i < size; ++i) {
    s += kDigits[bytes[i] >> 4];
    s += kDigits[bytes[i] & 15];
  }
  return s;
}

std::vector<std::uint8_t> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename T>
T get(const std::vector<std::uint8_t>& bytes, std::size_t at, const std::string& what) {
  if (at + sizeof(T) > bytes.size()) throw std::runtime_error(what + ": past the end of the file");
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof(T));
  return v;
}

template <typename T>
void put(std::vector<std::uint8_t>& bytes, std::size_t at, T v) {
  std::memcpy(bytes.data() + at, &v, sizeof(T));
}

// A LASzip handle; every call is checked, its error message thrown.
class Laszip {
 public:
  Laszip() {
    if (laszip_create(&h_)) throw std::runtime_error("laszip_create failed");
  }
  ~Laszip() { laszip_destroy(h_); }
  Laszip(const Laszip&) = delete;
  Laszip& operator=(const Laszip&) = delete;
  laszip_POINTER get() const { return h_; }
  void check(laszip_I32 rc, const std::string& what) const {
    if (rc == 0) return;
    laszip_CHAR* error = nullptr;
    laszip_get_error(h_, &error);
    throw std::runtime_error(what + ": " + (error ? error : "(no message)"));
  }

 private:
  laszip_POINTER h_ = nullptr;
};

// The raw LAS 1.4 record (point formats 6-10) of a point LASzip decoded.
void rawRecord(const laszip_point& p, int format, std::uint8_t* rec) {
  std::memcpy(rec + 0, &p.X, 4);
  std::memcpy(rec + 4, &p.Y, 4);
  std::memcpy(rec + 8, &p.Z, 4);
  std::memcpy(rec + 12, &p.intensity, 2);
  rec[14] = std::uint8_t(p.extended_return_number | p.extended_number_of_returns << 4);
  rec[15] = std::uint8_t(p.extended_classification_flags | p.extended_scanner_channel << 4 |
                         p.scan_direction_flag << 6 | p.edge_of_flight_line << 7);
  rec[16] = p.extended_classification;
  rec[17] = p.user_data;
  std::memcpy(rec + 18, &p.extended_scan_angle, 2);
  std::memcpy(rec + 20, &p.point_source_ID, 2);
  std::memcpy(rec + 22, &p.gps_time, 8);
  std::size_t at = 30;
  if (format == 7) {
    std::memcpy(rec + at, p.rgb, 6);
    at += 6;
  } else if (format == 8 || format == 10) {
    std::memcpy(rec + at, p.rgb, 8);
    at += 8;
  }
  if (format == 9 || format == 10) {
    std::memcpy(rec + at, p.wave_packet, 29);
    at += 29;
  }
  if (p.num_extra_bytes > 0) std::memcpy(rec + at, p.extra_bytes, std::size_t(p.num_extra_bytes));
}

struct Decoded {
  int format = 0;
  std::size_t record_length = 0;
  std::vector<std::uint8_t> records;
};

Decoded decodeWithLaszip(const std::string& path) {
  Laszip reader;
  laszip_BOOL compressed = 0;
  reader.check(laszip_open_reader(reader.get(), path.c_str(), &compressed), path);
  laszip_header* header = nullptr;
  reader.check(laszip_get_header_pointer(reader.get(), &header), path);
  laszip_point* point = nullptr;
  reader.check(laszip_get_point_pointer(reader.get(), &point), path);
  Decoded d;
  d.format = header->point_data_format & 63;
  if (d.format < 6 || d.format > 10) {
    throw std::runtime_error(path + ": point format " + std::to_string(d.format) +
                             ", expected 6-10");
  }
  d.record_length = header->point_data_record_length;
  const std::uint64_t count = header->extended_number_of_point_records
                                  ? header->extended_number_of_point_records
                                  : header->number_of_point_records;
  d.records.resize(count * d.record_length);
  for (std::uint64_t i = 0; i < count; ++i) {
    reader.check(laszip_read_point(reader.get()), path + ": point " + std::to_string(i));
    rawRecord(*point, d.format, d.records.data() + i * d.record_length);
  }
  reader.check(laszip_close_reader(reader.get()), path);
  return d;
}

// Where a LAZ file's chunks lie: after the 8-byte chunk table offset at the start of the point
// data, up to the chunk table; and how many the table lists.
struct ChunkSpan {
  std::size_t begin = 0, end = 0, chunks = 0;
};

ChunkSpan chunkSpan(const std::vector<std::uint8_t>& file, const std::string& path) {
  const auto points = get<std::uint32_t>(file, 96, path + ": offset to point data");
  const auto table = get<std::int64_t>(file, points, path + ": chunk table offset");
  if (table <= std::int64_t(points) + 8 || std::uint64_t(table) + 8 > file.size()) {
    throw std::runtime_error(path + ": chunk table offset " + std::to_string(table) +
                             " outside the file");
  }
  return {points + 8, std::size_t(table),
          get<std::uint32_t>(file, std::size_t(table) + 4, path + ": chunk count")};
}

// The LASzip VLR's chunk size and item versions, checked against what was asked for.
void checkLaszipVlr(const std::vector<std::uint8_t>& file, const std::string& path,
                    std::size_t chunk, std::uint16_t version) {
  std::size_t at = get<std::uint16_t>(file, 94, path + ": header size");
  const auto vlrs = get<std::uint32_t>(file, 100, path + ": VLR count");
  for (std::uint32_t v = 0; v < vlrs; ++v) {
    if (at + 54 > file.size()) throw std::runtime_error(path + ": VLR header past the end");
    const std::string user(reinterpret_cast<const char*>(file.data() + at + 2),
                           strnlen(reinterpret_cast<const char*>(file.data() + at + 2), 16));
    const auto record = get<std::uint16_t>(file, at + 18, path + ": VLR record id");
    const auto length = get<std::uint16_t>(file, at + 20, path + ": VLR length");
    const std::size_t data = at + 54;
    if (user == "laszip encoded" && record == 22204) {
      const auto chunk_size = get<std::uint32_t>(file, data + 12, path + ": chunk size");
      if (chunk_size != chunk) {
        throw std::runtime_error(path + ": LASzip wrote chunks of " + std::to_string(chunk_size) +
                                 ", asked for " + std::to_string(chunk));
      }
      const auto items = get<std::uint16_t>(file, data + 32, path + ": item count");
      for (std::uint16_t i = 0; i < items; ++i) {
        const auto item_version =
            get<std::uint16_t>(file, data + 34 + 6 * i + 4, path + ": item version");
        if (item_version != version) {
          throw std::runtime_error(path + ": LASzip wrote item version " +
                                   std::to_string(item_version) + ", asked for " +
                                   std::to_string(version));
        }
      }
      return;
    }
    at = data + length;
  }
  throw std::runtime_error(path + ": no LASzip VLR");
}

// An uncompressed LAS file of `records`: LAS 1.4 (375-byte header) or 1.5 (393 bytes: the GPS
// time range and time offset added), no VLRs.
void writeLas(const std::string& path, int format, std::size_t extra_bytes, std::size_t count,
              const std::vector<std::byte>& records, int minor) {
  const std::size_t header_size = minor >= 5 ? 393 : 375;
  std::vector<std::uint8_t> h(header_size, 0);
  std::memcpy(h.data(), "LASF", 4);
  put<std::uint16_t>(h, 6, 0x10);  // global encoding: the CRS is WKT (required for formats 6-10)
  h[24] = 1;
  h[25] = std::uint8_t(minor);
  std::memcpy(h.data() + 26, "parallax laszip_expectations", 28);
  put<std::uint16_t>(h, 94, std::uint16_t(header_size));
  put<std::uint32_t>(h, 96, std::uint32_t(header_size));
  h[104] = std::uint8_t(format);
  put<std::uint16_t>(h, 105, std::uint16_t(syntheticRecordLength(format, extra_bytes)));
  for (int axis = 0; axis < 3; ++axis) put<double>(h, 131 + 8 * axis, 0.01);
  put<std::uint64_t>(h, 247, count);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(h.data()), std::streamsize(h.size()));
  out.write(reinterpret_cast<const char*>(records.data()), std::streamsize(records.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

// LASzip's layered compression of `las` into `laz`, in chunks of `chunk` points.
void compressWithLaszip(const std::string& las, const std::string& laz, std::size_t chunk) {
  Laszip reader, writer;
  laszip_BOOL compressed = 0;
  reader.check(laszip_open_reader(reader.get(), las.c_str(), &compressed), las);
  laszip_header* header = nullptr;
  reader.check(laszip_get_header_pointer(reader.get(), &header), las);
  laszip_point* point = nullptr;
  reader.check(laszip_get_point_pointer(reader.get(), &point), las);
  writer.check(laszip_set_header(writer.get(), header), laz);
  writer.check(laszip_request_native_extension(writer.get(), 1), laz);
  writer.check(laszip_set_chunk_size(writer.get(), laszip_U32(chunk)), laz);
  writer.check(laszip_open_writer(writer.get(), laz.c_str(), 1), laz);
  for (std::uint64_t i = 0; i < header->extended_number_of_point_records; ++i) {
    reader.check(laszip_read_point(reader.get()), las + ": point " + std::to_string(i));
    writer.check(laszip_set_point(writer.get(), point), laz + ": point " + std::to_string(i));
    writer.check(laszip_write_point(writer.get()), laz + ": point " + std::to_string(i));
  }
  writer.check(laszip_close_writer(writer.get()), laz);
  reader.check(laszip_close_reader(reader.get()), las);
}

void printDecoded(const std::string& data, const char* name, std::vector<std::size_t> records) {
  const std::string path = data + "/laz/" + name;
  const Decoded d = decodeWithLaszip(path);
  const std::size_t count = d.records.size() / d.record_length;
  std::printf("expectFileDecodesAsLaszip(\"%s\", %zu, %zu, 0x%016" PRIx64 "ull, {\n", name, count,
              chunkSpan(readFile(path), path).chunks, fnv1a64(d.records));
  for (std::size_t i : records) {
    if (i >= count) throw std::runtime_error(path + ": no record " + std::to_string(i));
    std::printf("{%zu, \"%s\"},\n", i,
                hex(d.records.data() + i * d.record_length, d.record_length).c_str());
  }
  std::printf("});\n");
}

struct EncodeCase {
  SyntheticSpec spec;
  std::size_t chunk;
  std::uint16_t version;
};

void printEncoded(const std::string& scratch, const EncodeCase& c) {
  const SyntheticSpec& s = c.spec;
  const std::vector<std::byte> records = makeSyntheticRecords(s);
  const std::string stem = scratch + "/format" + std::to_string(s.format) + "_v" +
                           std::to_string(c.version) + "_chunk" + std::to_string(c.chunk);
  const std::string las = stem + ".las", laz = stem + ".laz";
  writeLas(las, s.format, s.extra_bytes, s.count, records, c.version == 4 ? 5 : 4);
  compressWithLaszip(las, laz, c.chunk);

  const std::vector<std::uint8_t> file = readFile(laz);
  checkLaszipVlr(file, laz, c.chunk, c.version);
  const Decoded back = decodeWithLaszip(laz);
  if (back.records.size() != records.size() ||
      std::memcmp(back.records.data(), records.data(), records.size()) != 0) {
    throw std::runtime_error(laz + ": LASzip does not decode its output to the input records");
  }
  const ChunkSpan span = chunkSpan(file, laz);
  const std::vector<std::uint8_t> chunks(file.begin() + std::ptrdiff_t(span.begin),
                                         file.begin() + std::ptrdiff_t(span.end));

  std::printf("{{.format = %d", s.format);
  if (s.extra_bytes != 0) std::printf(", .extra_bytes = %zu", s.extra_bytes);
  std::printf(", .count = %zu, .seed = %" PRIu64, s.count, s.seed);
  if (s.quiet_span != 0) std::printf(", .quiet_span = %zu", s.quiet_span);
  std::printf("}, %zu, %u, %zu, 0x%016" PRIx64 "ull},\n", c.chunk, unsigned(c.version),
              chunks.size(), fnv1a64(chunks));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s <test data folder holding laz/> <scratch folder>\n", argv[0]);
    return 2;
  }
  const std::string data = argv[1], scratch = argv[2];
  try {
    std::filesystem::create_directories(scratch);
    std::printf("void f() {\n");
    printDecoded(data, "simple.copc.laz", {0, 1, 17, 532, 1063, 1064});
    printDecoded(data, "ellipsoid.copc.laz", {0, 1, 20000, 31337, 50001, 99999});

    // The inputs of EncoderWritesLaszipBytes: several scanner channels, multiple returns, GPS
    // times that jump between sequences, quiet chunks, and chunks of two points, the last of one.
    const EncodeCase cases[] = {
        {{.format = 6, .count = 12000, .seed = 2, .quiet_span = 3000}, 3000, 3},
        {{.format = 7, .count = 12000, .seed = 4, .quiet_span = 3000}, 3000, 3},
        {{.format = 7, .count = 12000, .seed = 4, .quiet_span = 3000}, 3000, 4},
        {{.format = 8, .extra_bytes = 5, .count = 12000, .seed = 6, .quiet_span = 2500}, 2500, 3},
        {{.format = 8, .extra_bytes = 5, .count = 12000, .seed = 6, .quiet_span = 2500}, 2500, 4},
        {{.format = 9, .extra_bytes = 2, .count = 8000, .seed = 9, .quiet_span = 2000}, 2000, 4},
        {{.format = 10, .extra_bytes = 4, .count = 8000, .seed = 11, .quiet_span = 2000}, 2000, 3},
        {{.format = 7, .extra_bytes = 1, .count = 5, .seed = 12}, 2, 3},
    };
    std::printf("const LaszipOutput cases[] = {\n");
    for (const EncodeCase& c : cases) printEncoded(scratch, c);
    std::printf("};\n}\n");
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "laszip_expectations: %s\n", e.what());
    return 1;
  }
  return 0;
}
