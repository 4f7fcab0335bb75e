#include "core/error.h"

#include <cstdio>
#include <string_view>

namespace parallax {
namespace {

// The length of the valid UTF-8 sequence at the start of `text` that is not a control character
// (C1, U+0080-U+009F, is one), or 0. Overlong forms, surrogates and code points past U+10FFFF are
// invalid (RFC 3629 section 4).
std::size_t printableUtf8Length(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  std::size_t length = 0;
  char32_t code = 0;
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2, code = lead & 0x1fu;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3, code = lead & 0x0fu;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4, code = lead & 0x07u;
  } else {
    return 0;
  }
  if (text.size() < length) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xc0u) != 0x80u) return 0;
    code = (code << 6) | (byte(i) & 0x3fu);
  }
  const char32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < smallest[length] || (code >= 0xd800 && code <= 0xdfff) || code > 0x10ffff ||
      code <= 0x9f) {
    return 0;
  }
  return length;
}

// The message as a terminal can show it: names and numbers read from a damaged file (a PLY
// element or property name, a PCD field) may hold any bytes, and a control character or an
// escape sequence in them would garble the terminal or forge text. Printable ASCII and valid
// UTF-8 (file names, names in other scripts) are kept; every other byte is written \xNN.
std::string printableMessage(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte >= 0x20 && byte < 0x7f) {
      out += text[i++];
      continue;
    }
    if (const std::size_t length = printableUtf8Length(text.substr(i))) {
      out.append(text.substr(i, length));
      i += length;
      continue;
    }
    char escaped[8];
    std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
    out += escaped;
    ++i;
  }
  return out;
}

// A name read from the file (an element, a property) at most this long in a message: a fuzzed
// PLY header's 60 000-byte property name need not be repeated whole.
constexpr std::size_t kMaxNameBytes = 120;

std::string shortName(const std::string& name) {
  if (name.size() <= kMaxNameBytes) return name;
  return name.substr(0, kMaxNameBytes) + "...";
}

}  // namespace

std::string formatInputError(const InputErrorInfo& info) {
  std::string message = info.file.empty() ? std::string("<input>") : info.file;
  std::string where;
  auto add = [&where](const std::string& part) {
    where += where.empty() ? "" : ", ";
    where += part;
  };
  if (info.line) add("line " + std::to_string(*info.line));
  if (info.byte_offset) add("byte offset " + std::to_string(*info.byte_offset));
  if (!info.element.empty()) add("element '" + shortName(info.element) + "'");
  if (!info.property.empty()) add("property '" + shortName(info.property) + "'");
  if (!where.empty()) message += ": " + where;
  if (!info.expected.empty()) message += ": expected " + info.expected;
  if (!info.found.empty()) message += (info.expected.empty() ? ": " : ", found ") + info.found;
  if (!info.hint.empty()) message += ". " + info.hint;
  return printableMessage(message);
}

InputError::InputError(InputErrorInfo info)
    : std::runtime_error(formatInputError(info)), info_(std::move(info)) {}

std::string quoteInput(std::string_view text, std::size_t max_chars) {
  std::string out = "'";
  std::size_t shown = 0;
  for (char c : text) {
    if (shown == max_chars) {
      out += "...";
      break;
    }
    auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f && c != '\'') {
      out += c;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    }
    ++shown;
  }
  out += "'";
  return out;
}

}  // namespace parallax
