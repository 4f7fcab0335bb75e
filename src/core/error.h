// Input errors: everything a user needs to find and fix a bad file.
//
// Programming mistakes are assertions; bad input is an InputError, which the application reports
// (library code never exits). The message names the file, where in it (byte offset or line), the
// element and property, what was expected, what was found, and a way out when there is one.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace parallax {

struct InputErrorInfo {
  std::string file;
  std::optional<std::uint64_t> byte_offset;
  std::optional<std::uint64_t> line;  // 1-based
  std::string element;
  std::string property;
  std::string expected;  // "a number", "at most 3 values", ...
  std::string found;     // what was there instead
  std::string hint;      // a way out, when there is one
};

class InputError : public std::runtime_error {
 public:
  explicit InputError(InputErrorInfo info);
  const InputErrorInfo& info() const { return info_; }

 private:
  InputErrorInfo info_;
};

// "file: line 12, element 'vertex', property 'x': expected a number, found 'abc'. hint"
// The message is printable whatever the parts hold: control characters (C0, DEL, C1) and bytes
// that are not valid UTF-8 are written \xNN, valid UTF-8 is kept; the element and the property,
// often names read from the file, are cut to their first 120 bytes ("...").
std::string formatInputError(const InputErrorInfo& info);

// Quotes a piece of untrusted input for a message: at most `max_chars` characters, control
// characters and non-ASCII bytes escaped, so a binary file cannot garble the terminal.
std::string quoteInput(std::string_view text, std::size_t max_chars = 40);

}  // namespace parallax
