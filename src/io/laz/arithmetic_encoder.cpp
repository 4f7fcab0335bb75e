#include "io/laz/arithmetic_encoder.h"

#include <cassert>

namespace parallax::laz {

void ArithmeticEncoder::propagateCarry() {
  // The interval base overflowed: add one to the bytes already out, from the last one back,
  // turning trailing 0xFF bytes into 0x00. The first byte of a stream can never overflow (the
  // base starts at 0 and the interval never passes 2^32 above it).
  std::size_t i = out_->size();
  while (i > first_) {
    --i;
    if ((*out_)[i] != 0xFF) {
      ++(*out_)[i];
      return;
    }
    (*out_)[i] = 0;
  }
  assert(false && "ArithmeticEncoder: carry out of the first byte of the stream");
}

std::size_t ArithmeticEncoder::finish() {
  // Choose a value inside the final interval with as few significant bytes as possible: one
  // more byte when the interval is long enough, otherwise two (FastAC's termination).
  const std::uint32_t before = base_;
  bool third_zero = true;
  if (length_ > 2 * kMinLength) {
    base_ += kMinLength;
    length_ = kMinLength >> 1;
  } else {
    base_ += kMinLength >> 1;
    length_ = kMinLength >> 9;
    third_zero = false;
  }
  if (base_ < before) propagateCarry();
  renormalize();
  // The decoder reads four bytes ahead of what it has decided: pad with zeros so it never
  // reads past the stream (2 + 1 after one final byte, 2 after two).
  out_->push_back(0);
  out_->push_back(0);
  if (third_zero) out_->push_back(0);
  return out_->size() - first_;
}

}  // namespace parallax::laz
