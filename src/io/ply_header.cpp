#include "io/ply_header.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <string_view>

#include "core/error.h"

namespace parallax {
namespace {

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isBlank(line[i])) ++i;
    std::size_t start = i;
    while (i < line.size() && !isBlank(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

// The text after the keyword, without leading blanks and the line end.
std::string restOfLine(std::string_view line, std::string_view keyword) {
  std::string_view rest = line.substr(line.find(keyword) + keyword.size());
  while (!rest.empty() && isBlank(rest.front())) rest.remove_prefix(1);
  while (!rest.empty() && isBlank(rest.back())) rest.remove_suffix(1);
  return std::string(rest);
}

class HeaderParser {
 public:
  HeaderParser(std::span<const std::byte> bytes, const std::string& file)
      : text_(reinterpret_cast<const char*>(bytes.data()), bytes.size()), file_(file) {}

  PlyHeader parse() {
    checkMagic();
    bool have_format = false;
    for (;;) {
      std::string_view line = nextLine();
      auto words = splitWords(line);
      if (words.empty()) continue;  // tolerated: some writers leave blank header lines
      std::string_view keyword = words[0];
      if (keyword == "end_header") {
        if (words.size() != 1) {
          fail("'end_header' alone on its line (blanks after it are allowed)",
               quoteInput(joined(words)));
        }
        break;
      }
      if (keyword == "format") {
        parseFormat(words);
        have_format = true;
      } else if (keyword == "comment") {
        header_.comments.push_back(restOfLine(line, "comment"));
      } else if (keyword == "obj_info") {
        header_.obj_info.push_back(restOfLine(line, "obj_info"));
      } else if (keyword == "element") {
        parseElement(words);
      } else if (keyword == "property") {
        parseProperty(words);
      } else {
        fail("a header keyword (format, element, property, comment, obj_info, end_header)",
             quoteInput(keyword));
      }
    }
    if (!have_format) {
      fail("a 'format' line before end_header", "none", "");
    }
    header_.body_offset = pos_;
    header_.body_line = line_number_ + 1;
    return std::move(header_);
  }

 private:
  [[noreturn]] void fail(std::string expected, std::string found, std::string element = "",
                         std::string property = "", std::string hint = "") {
    throw InputError({.file = file_,
                      .line = line_number_,
                      .element = std::move(element),
                      .property = std::move(property),
                      .expected = std::move(expected),
                      .found = std::move(found),
                      .hint = std::move(hint)});
  }

  // The first line is "ply". Exporters in the wild add blanks after it ("ply " from some
  // Python writers, "ply\t"), or end it with CR LF; rply, PDAL and CloudCompare take all of
  // these, so we do too. Anything else on the line is a broken header.
  void checkMagic() {
    const bool starts_ply = text_.substr(0, 3) == "ply";
    if (!starts_ply) {
      line_number_ = 1;
      throw InputError({.file = file_,
                        .byte_offset = 0,
                        .line = 1,
                        .expected = "a PLY file starting with the line 'ply'",
                        .found = text_.empty() ? std::string("an empty file")
                                               : quoteInput(text_.substr(0, 16))});
    }
    const std::size_t limit = std::min(text_.size(), kMaxPlyHeaderBytes);
    const bool has_lf = std::memchr(text_.data(), '\n', limit) != nullptr;
    if (!has_lf && text_.substr(0, limit).find('\r') != std::string_view::npos) {
      line_number_ = 1;
      fail("header lines ending in LF (or CR LF)", "lines ending in CR alone (classic Mac OS)", "",
           "", "the header's line ends must be converted to LF");
    }
    std::string_view line = nextLine();
    std::string_view rest = line.substr(3);
    while (!rest.empty() && isBlank(rest.front())) rest.remove_prefix(1);
    if (!rest.empty()) {
      fail("the first line 'ply' (blanks after it are allowed)",
           quoteInput(line.substr(0, std::min<std::size_t>(line.size(), 40))));
    }
  }

  // The next line without its end (LF or CRLF); throws when the header does not end.
  std::string_view nextLine() {
    ++line_number_;
    std::size_t limit = std::min(text_.size(), kMaxPlyHeaderBytes);
    if (pos_ >= limit) failUnterminated(limit);
    const void* found = std::memchr(text_.data() + pos_, '\n', limit - pos_);
    if (found == nullptr) failUnterminated(limit);
    std::size_t end = std::size_t(static_cast<const char*>(found) - text_.data());
    std::string_view line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return line;
  }

  [[noreturn]] void failUnterminated(std::size_t limit) {
    if (limit == kMaxPlyHeaderBytes) {
      throw InputError({.file = file_,
                        .byte_offset = limit,
                        .expected = "'end_header' within the first " +
                                    std::to_string(kMaxPlyHeaderBytes) + " bytes",
                        .found = "a header that goes on",
                        .hint = "the file is not a PLY file, or its header is damaged"});
    }
    throw InputError({.file = file_,
                      .byte_offset = pos_,
                      .line = line_number_,
                      .expected = "'end_header'",
                      .found = "the end of the file inside the header",
                      .hint = "the file is truncated"});
  }

  void parseFormat(const std::vector<std::string_view>& words) {
    if (words.size() != 3)
      fail("'format <ascii|binary_little_endian|binary_big_endian> 1.0'",
           quoteInput(joined(words)));
    if (words[1] == "ascii") {
      header_.format = PlyFormat::Ascii;
    } else if (words[1] == "binary_little_endian") {
      header_.format = PlyFormat::BinaryLittleEndian;
    } else if (words[1] == "binary_big_endian") {
      header_.format = PlyFormat::BinaryBigEndian;
    } else {
      fail("a format of ascii, binary_little_endian or binary_big_endian", quoteInput(words[1]));
    }
    // Every PLY writer in the wild writes 1.0; "1" is accepted too. Anything else might mean a
    // layout we do not know, so refuse rather than guess.
    if (words[2] != "1.0" && words[2] != "1") {
      fail("format version 1.0", quoteInput(words[2]), "", "", "PLY has only ever had version 1.0");
    }
    header_.version = std::string(words[2]);
  }

  void parseElement(const std::vector<std::string_view>& words) {
    if (words.size() != 3) fail("'element <name> <count>'", quoteInput(joined(words)));
    PlyElement element;
    element.name = std::string(words[1]);
    element.header_line = line_number_;
    std::string_view count = words[2];
    auto [end, error] = std::from_chars(count.data(), count.data() + count.size(), element.count);
    if (error != std::errc() || end != count.data() + count.size()) {
      fail("a non-negative whole number of records", quoteInput(count), element.name);
    }
    header_.elements.push_back(std::move(element));
  }

  void parseProperty(const std::vector<std::string_view>& words) {
    if (header_.elements.empty()) {
      fail("'element' before the first 'property'", quoteInput(joined(words)));
    }
    PlyElement& element = header_.elements.back();
    PlyProperty property;
    property.header_line = line_number_;
    if (words.size() >= 2 && words[1] == "list") {
      if (words.size() != 5) {
        fail("'property list <count type> <item type> <name>'", quoteInput(joined(words)),
             element.name);
      }
      property.is_list = true;
      property.list_count_type = parseType(words[2], element.name, words[4]);
      if (isFloatingPoint(property.list_count_type)) {
        fail("an integer type for the list count", quoteInput(words[2]), element.name,
             std::string(words[4]));
      }
      property.type = parseType(words[3], element.name, words[4]);
      property.name = std::string(words[4]);
    } else {
      if (words.size() != 3) {
        fail("'property <type> <name>'", quoteInput(joined(words)), element.name);
      }
      property.type = parseType(words[1], element.name, words[2]);
      property.name = std::string(words[2]);
    }
    element.properties.push_back(std::move(property));
  }

  ScalarType parseType(std::string_view word, const std::string& element,
                       std::string_view property) {
    auto type = parseScalarType(word);
    if (!type) {
      fail("a type of char uchar short ushort int uint float double (or int8 ... float64)",
           quoteInput(word), element, std::string(property));
    }
    return *type;
  }

  static std::string joined(const std::vector<std::string_view>& words) {
    std::string text;
    for (auto word : words) {
      if (!text.empty()) text += ' ';
      text += word;
    }
    return text;
  }

  std::string_view text_;
  const std::string& file_;
  std::size_t pos_ = 0;
  std::uint64_t line_number_ = 0;
  PlyHeader header_;
};

}  // namespace

std::string_view plyFormatName(PlyFormat format) {
  switch (format) {
    case PlyFormat::Ascii:
      return "ascii";
    case PlyFormat::BinaryLittleEndian:
      return "binary_little_endian";
    case PlyFormat::BinaryBigEndian:
      return "binary_big_endian";
  }
  return "?";
}

bool PlyElement::hasLists() const {
  for (const auto& property : properties) {
    if (property.is_list) return true;
  }
  return false;
}

std::size_t PlyElement::fixedRecordSize() const {
  std::size_t size = 0;
  for (const auto& property : properties) size += scalarSize(property.type);
  return size;
}

std::size_t PlyElement::minimumRecordSize() const {
  std::size_t size = 0;
  for (const auto& property : properties) {
    size += property.is_list ? scalarSize(property.list_count_type) : scalarSize(property.type);
  }
  return size;
}

int PlyElement::findProperty(std::string_view property_name) const {
  for (std::size_t i = 0; i < properties.size(); ++i) {
    if (properties[i].name == property_name) return int(i);
  }
  return -1;
}

int PlyHeader::pointElement() const {
  for (std::string_view name : {"vertex", "vertices", "point", "points"}) {
    for (std::size_t i = 0; i < elements.size(); ++i) {
      if (elements[i].name == name) return int(i);
    }
  }
  return -1;
}

PlyHeader parsePlyHeader(std::span<const std::byte> bytes, const std::string& file_name) {
  return HeaderParser(bytes, file_name).parse();
}

std::string formatPlyHeader(const PlyHeader& header) {
  std::string text = "ply\nformat ";
  text += plyFormatName(header.format);
  text += " 1.0\n";
  for (const auto& comment : header.comments) text += "comment " + comment + "\n";
  for (const auto& info : header.obj_info) text += "obj_info " + info + "\n";
  for (const auto& element : header.elements) {
    text += "element " + element.name + " " + std::to_string(element.count) + "\n";
    for (const auto& property : element.properties) {
      text += "property ";
      if (property.is_list) {
        text += "list ";
        text += scalarName(property.list_count_type);
        text += ' ';
      }
      text += scalarName(property.type);
      text += ' ' + property.name + "\n";
    }
  }
  text += "end_header\n";
  return text;
}

}  // namespace parallax
