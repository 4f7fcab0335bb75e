#include "core/error.h"

#include <cstdio>

namespace parallax {

std::string formatInputError(const InputErrorInfo& info) {
  std::string message = info.file.empty() ? std::string("<input>") : info.file;
  std::string where;
  auto add = [&where](const std::string& part) {
    where += where.empty() ? "" : ", ";
    where += part;
  };
  if (info.line) add("line " + std::to_string(*info.line));
  if (info.byte_offset) add("byte offset " + std::to_string(*info.byte_offset));
  if (!info.element.empty()) add("element '" + info.element + "'");
  if (!info.property.empty()) add("property '" + info.property + "'");
  if (!where.empty()) message += ": " + where;
  if (!info.expected.empty()) message += ": expected " + info.expected;
  if (!info.found.empty()) message += (info.expected.empty() ? ": " : ", found ") + info.found;
  if (!info.hint.empty()) message += ". " + info.hint;
  return message;
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
