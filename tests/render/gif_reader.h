#pragma once
// A GIF reader for the tests, written from the GIF89a specification independently of GifWriter:
// the blocks GifWriter emits (global palette, NETSCAPE2.0 loop, graphic control, full-frame
// images without local palettes) and the LZW decoder. Malformed input throws std::runtime_error.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/image.h"

namespace flsd::testutil {

struct GifFrame {
  int delay_cs = -1;  // from the graphic control extension before it; -1 if none
  int width = 0, height = 0;
  std::vector<uint8_t> indices;  // palette index per pixel, rows top first
  int clear_codes = 0;           // in its LZW stream, the leading one included
};

struct DecodedGif {
  int width = 0, height = 0;
  std::vector<Rgb> palette;
  int loop_count = -1;  // NETSCAPE2.0's; -1 if the file has none
  std::vector<GifFrame> frames;
  bool trailer = false;  // ends with 0x3B and nothing after

  Rgb Color(const GifFrame& frame, int x, int y) const { return palette.at(frame.indices.at(y * frame.width + x)); }
};

class GifParser {
 public:
  explicit GifParser(const std::string& bytes) : bytes_(bytes) {}

  DecodedGif Parse() {
    DecodedGif gif;
    if (bytes_.compare(0, 6, "GIF89a") != 0) throw std::runtime_error("no GIF89a signature");
    at_ = 6;
    gif.width = U16();
    gif.height = U16();
    const int packed = Byte();
    Byte();  // background colour index
    Byte();  // pixel aspect ratio
    if (packed & 0x80) {
      const int colors = 1 << ((packed & 7) + 1);
      for (int i = 0; i < colors; ++i) {
        const uint8_t r = Byte(), g = Byte(), b = Byte();
        gif.palette.push_back({r, g, b});
      }
    }
    int pending_delay = -1;
    while (at_ < bytes_.size()) {
      const int introducer = Byte();
      if (introducer == 0x3B) {
        gif.trailer = at_ == bytes_.size();
        return gif;
      }
      if (introducer == 0x21) {
        const int label = Byte();
        const std::vector<std::string> blocks = SubBlocks();
        if (label == 0xF9) {
          if (blocks.size() != 1 || blocks[0].size() != 4) throw std::runtime_error("bad graphic control extension");
          pending_delay = static_cast<uint8_t>(blocks[0][1]) | (static_cast<uint8_t>(blocks[0][2]) << 8);
        } else if (label == 0xFF && blocks.size() == 2 && blocks[0] == "NETSCAPE2.0" && blocks[1].size() == 3 &&
                   blocks[1][0] == 1) {
          gif.loop_count = static_cast<uint8_t>(blocks[1][1]) | (static_cast<uint8_t>(blocks[1][2]) << 8);
        }
      } else if (introducer == 0x2C) {
        gif.frames.push_back(ParseImage(pending_delay));
        pending_delay = -1;
      } else {
        throw std::runtime_error("unknown block introducer " + std::to_string(introducer));
      }
    }
    return gif;  // no trailer
  }

 private:
  GifFrame ParseImage(int delay_cs) {
    GifFrame frame;
    frame.delay_cs = delay_cs;
    U16();  // left
    U16();  // top
    frame.width = U16();
    frame.height = U16();
    if (Byte() != 0) throw std::runtime_error("local palette or interlacing, which the writer never uses");
    const int min_code_size = Byte();
    std::string data;
    for (const std::string& block : SubBlocks()) data += block;
    frame.indices = LzwDecode(data, min_code_size, &frame.clear_codes);
    if (frame.indices.size() != static_cast<size_t>(frame.width) * frame.height) {
      throw std::runtime_error("decoded " + std::to_string(frame.indices.size()) + " pixels, expected " +
                               std::to_string(frame.width * frame.height));
    }
    return frame;
  }

  static std::vector<uint8_t> LzwDecode(const std::string& data, int min_code_size, int* clear_codes) {
    const int clear = 1 << min_code_size, end = clear + 1;
    std::vector<std::vector<uint8_t>> table(clear);
    for (int i = 0; i < clear; ++i) table[i] = {static_cast<uint8_t>(i)};
    std::vector<uint8_t> out;
    size_t bit = 0;
    int width = min_code_size + 1, previous = -1;
    while (true) {
      if (bit + width > 8 * data.size()) throw std::runtime_error("LZW data ends without an end code");
      int code = 0;
      for (int i = 0; i < width; ++i, ++bit) {
        code |= ((static_cast<uint8_t>(data[bit / 8]) >> (bit % 8)) & 1) << i;
      }
      if (code == clear) {
        ++*clear_codes;
        table.resize(end + 1);
        width = min_code_size + 1;
        previous = -1;
        continue;
      }
      if (code == end) return out;
      if (previous < 0) {
        if (code >= clear) throw std::runtime_error("first code after a clear is not a single index");
        out.push_back(static_cast<uint8_t>(code));
        previous = code;
        continue;
      }
      std::vector<uint8_t> entry;
      if (code < static_cast<int>(table.size())) {
        entry = table[code];
      } else if (code == static_cast<int>(table.size())) {  // the string being defined: prev + its first
        entry = table[previous];
        entry.push_back(table[previous][0]);
      } else {
        throw std::runtime_error("code " + std::to_string(code) + " beyond the table");
      }
      out.insert(out.end(), entry.begin(), entry.end());
      if (table.size() < 4096) {
        std::vector<uint8_t> added = table[previous];
        added.push_back(entry[0]);
        table.push_back(std::move(added));
        if (table.size() == (1u << width) && width < 12) ++width;
      }
      previous = code;
    }
  }

  std::vector<std::string> SubBlocks() {
    std::vector<std::string> blocks;
    for (int n = Byte(); n != 0; n = Byte()) {
      if (at_ + n > bytes_.size()) throw std::runtime_error("sub-block past the end");
      blocks.push_back(bytes_.substr(at_, n));
      at_ += n;
    }
    return blocks;
  }

  int Byte() {
    if (at_ >= bytes_.size()) throw std::runtime_error("unexpected end of file");
    return static_cast<uint8_t>(bytes_[at_++]);
  }
  int U16() {
    const int lo = Byte();
    return lo | (Byte() << 8);
  }

  const std::string& bytes_;
  size_t at_ = 0;
};

inline DecodedGif DecodeGif(const std::string& bytes) { return GifParser(bytes).Parse(); }

}  // namespace flsd::testutil
