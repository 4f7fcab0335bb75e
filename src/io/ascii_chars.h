// Character classes of ascii point records, shared by the general line parser
// (ply_ascii_decoder.cpp) and the fast path (ply_ascii_fast_decoder.cpp), so both agree on what
// separates values. By table: one load instead of a chain of compares, in the hottest loops.
#pragma once

namespace parallax::ply {

struct AsciiCharClasses {
  bool blank[256] = {};      // separates values within a line
  bool delimiter[256] = {};  // may follow a number: a blank or the line end
  constexpr AsciiCharClasses() {
    for (unsigned char c : {' ', '\t', '\r', '\v', '\f'}) blank[c] = delimiter[c] = true;
    delimiter[(unsigned char)'\n'] = true;
  }
};
inline constexpr AsciiCharClasses kAsciiChars;

inline bool isBlank(char c) {
  return kAsciiChars.blank[static_cast<unsigned char>(c)];
}
inline bool isDelimiter(char c) {
  return kAsciiChars.delimiter[static_cast<unsigned char>(c)];
}

}  // namespace parallax::ply
