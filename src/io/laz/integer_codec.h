// LASzip's integer compressor: codes an integer as the corrector c = real - prediction, in two
// steps: k, the number of significant bits of c (one adaptive symbol model per context), then
// c's position inside the interval that k selects (for k <= bits_high one adaptive model per k;
// above, its top bits_high bits adaptively and the rest raw). k = 0 leaves c in {0, 1}, coded by
// one adaptive bit model. Correctors wrap modulo the value range, so the range of the value
// (`bits` bits, or an explicit `range`) bounds every corrector.
//
// Source: M. Isenburg, "LASzip: lossless compression of LiDAR data", PE&RS 79(2), 2013,
// section "Compressing integers"; the constants are the format's. The point codecs read
// `lastK()` after a call: the k of one field is a context for the next.
#pragma once

#include <cstdint>
#include <vector>

#include "io/laz/arithmetic_decoder.h"
#include "io/laz/arithmetic_encoder.h"
#include "io/laz/arithmetic_models.h"

namespace parallax::laz {

struct IntegerCodecShape {
  std::uint32_t bits = 16;      // the value's width, when `range` is 0
  std::uint32_t contexts = 1;   // independent k models, chosen per call
  std::uint32_t bits_high = 8;  // the corrector bits coded adaptively for large k
  std::uint32_t range = 0;      // the value's range when it is not a power of two (0: 2^bits)
};

// The models of one integer compressor, and the corrector's bounds derived from its shape.
class IntegerModels {
 public:
  IntegerModels(const IntegerCodecShape& shape, bool for_decoding);
  // Every model back to its initial state (the start of a chunk). The symbol models are reset
  // on their first use after this call instead of here: a 32-bit codec has some 6 600 corrector
  // symbols, and a chunk of a few points (COPC's small nodes) would spend most of its time
  // resetting models it never uses. A model reset late is in exactly the state of one reset
  // early, so the stream is the same.
  void reset();

  SymbolModel& kModel(std::uint32_t context) {
    return fresh(k_models[context], k_generation[context]);
  }
  // The model of correctors with k significant bits (1..corr_bits).
  SymbolModel& correctorModel(std::uint32_t k) {
    return fresh(corrector[k - 1], corrector_generation[k - 1]);
  }

  std::uint32_t corr_bits = 0;   // significant bits of the largest corrector
  std::uint32_t corr_range = 0;  // 0 stands for 2^32
  std::int32_t corr_min = 0;
  std::int32_t corr_max = 0;
  std::uint32_t bits_high = 8;
  std::vector<SymbolModel> k_models;  // one per context: corr_bits + 1 symbols
  BitModel corrector0;                // k == 0: c is 0 or 1
  // k = 1..corr_bits (index k - 1): 2^min(k, bits_high) symbols.
  std::vector<SymbolModel> corrector;

 private:
  SymbolModel& fresh(SymbolModel& model, std::uint32_t& generation) {
    if (generation != generation_) {
      model.reset();
      generation = generation_;
    }
    return model;
  }

  // reset() advances generation_; a model whose generation differs is reset when next used.
  std::uint32_t generation_ = 0;
  std::vector<std::uint32_t> k_generation;
  std::vector<std::uint32_t> corrector_generation;
};

class IntegerDecoder {
 public:
  explicit IntegerDecoder(const IntegerCodecShape& shape) : models_(shape, true) {}
  void reset() { models_.reset(); }

  // The value whose corrector against `prediction` comes next in the stream, in `context`.
  std::int32_t decode(ArithmeticDecoder& dec, std::int32_t prediction, std::uint32_t context = 0);
  // k of the last decode (the corrector's significant bits).
  std::uint32_t lastK() const { return k_; }

 private:
  std::int32_t readCorrector(ArithmeticDecoder& dec, SymbolModel& k_model);

  IntegerModels models_;
  std::uint32_t k_ = 0;
};

class IntegerEncoder {
 public:
  explicit IntegerEncoder(const IntegerCodecShape& shape) : models_(shape, false) {}
  void reset() { models_.reset(); }

  void encode(ArithmeticEncoder& enc, std::int32_t prediction, std::int32_t real,
              std::uint32_t context = 0);
  std::uint32_t lastK() const { return k_; }

 private:
  void writeCorrector(ArithmeticEncoder& enc, std::int32_t c, SymbolModel& k_model);

  IntegerModels models_;
  std::uint32_t k_ = 0;
};

}  // namespace parallax::laz
