#include "render/image.h"

#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/check.h"

namespace flsd {

Image::Image(int w, int h, Rgb fill) : width(w), height(h), rgb(3 * static_cast<size_t>(w) * h) {
  FLSD_DEMAND(w >= 0 && h >= 0);
  for (size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = fill.r;
    rgb[i + 1] = fill.g;
    rgb[i + 2] = fill.b;
  }
}

Rgb Image::at(int x, int y) const {
  const uint8_t* p = &rgb[3 * (static_cast<size_t>(y) * width + x)];
  return {p[0], p[1], p[2]};
}

void Image::set(int x, int y, Rgb c) {
  uint8_t* p = &rgb[3 * (static_cast<size_t>(y) * width + x)];
  p[0] = c.r;
  p[1] = c.g;
  p[2] = c.b;
}

void FillRect(Image& image, int x, int y, int w, int h, Rgb color) {
  for (int row = std::max(y, 0); row < std::min(y + h, image.height); ++row) {
    for (int col = std::max(x, 0); col < std::min(x + w, image.width); ++col) image.set(col, row, color);
  }
}

void Blit(const Image& source, int x, int y, Image& target) {
  for (int row = 0; row < source.height; ++row) {
    if (y + row < 0 || y + row >= target.height) continue;
    for (int col = 0; col < source.width; ++col) {
      if (x + col >= 0 && x + col < target.width) target.set(x + col, y + row, source.at(col, row));
    }
  }
}

namespace {

// 5x7 digit glyphs, one row per entry, the most significant of 5 bits the leftmost pixel.
constexpr std::array<std::array<uint8_t, 7>, 10> kDigitGlyphs = {{
    {0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110},  // 0
    {0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110},  // 1
    {0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111},  // 2
    {0b11111, 0b00010, 0b00100, 0b00010, 0b00001, 0b10001, 0b01110},  // 3
    {0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010},  // 4
    {0b11111, 0b10000, 0b11110, 0b00001, 0b00001, 0b10001, 0b01110},  // 5
    {0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110},  // 6
    {0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b01000, 0b01000},  // 7
    {0b01110, 0b10001, 0b10001, 0b01110, 0b10001, 0b10001, 0b01110},  // 8
    {0b01110, 0b10001, 0b10001, 0b01111, 0b00001, 0b00010, 0b01100},  // 9
}};
constexpr int kGlyphWidth = 5, kGlyphHeight = 7;

}  // namespace

int DrawNumber(Image& image, int x, int y, int number, int scale, Rgb color, Rgb background) {
  FLSD_DEMAND(number >= 0 && scale > 0);
  const std::string digits = std::to_string(number);
  // one font pixel of margin around the digits, and one between them
  const int columns = static_cast<int>(digits.size()) * (kGlyphWidth + 1) + 1;
  FillRect(image, x, y, columns * scale, (kGlyphHeight + 2) * scale, background);
  for (size_t d = 0; d < digits.size(); ++d) {
    const auto& glyph = kDigitGlyphs[digits[d] - '0'];
    const int left = x + (1 + static_cast<int>(d) * (kGlyphWidth + 1)) * scale;
    for (int row = 0; row < kGlyphHeight; ++row) {
      for (int col = 0; col < kGlyphWidth; ++col) {
        if (glyph[row] & (1 << (kGlyphWidth - 1 - col))) {
          FillRect(image, left + col * scale, y + (1 + row) * scale, scale, scale, color);
        }
      }
    }
  }
  return columns * scale;
}

void WritePng(const Image& image, const std::string& path) {
  FLSD_DEMAND(image.rgb.size() == 3 * static_cast<size_t>(image.width) * image.height);
  WriteFileAtomically(path, [&](const std::string& temp) {
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width);
    png.height = static_cast<png_uint_32>(image.height);
    png.format = PNG_FORMAT_RGB;
    if (!png_image_write_to_file(&png, temp.c_str(), 0, image.rgb.data(), 3 * image.width, nullptr)) {
      throw InputError(path + ": cannot write the PNG: " + png.message);
    }
  });
}

// ---- GIF ----

namespace {

// The palette's levels per channel.
constexpr int kRedLevels = 6, kGreenLevels = 7, kBlueLevels = 6;

uint8_t LevelValue(int level, int levels) {
  return static_cast<uint8_t>((level * 255 + (levels - 1) / 2) / (levels - 1));
}

// The 4x4 Bayer matrix: thresholds spread evenly over space, for ordered dithering.
constexpr std::array<std::array<int, 4>, 4> kBayer = {{{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}}};

// The level of `value` at a pixel whose Bayer threshold is `bayer`: floor(value * (levels - 1)
// / 255 + t) with t = (2 bayer + 1) / 32 in (0, 1), so a value a fraction f of the way between
// two levels rounds up at a fraction f of the pixels, and a value on a level stays on it.
int DitheredLevel(int value, int levels, int bayer) {
  return (value * (levels - 1) * 32 + (2 * bayer + 1) * 255) / (255 * 32);
}

void AppendU16(std::string& out, int v) {
  out.push_back(static_cast<char>(v & 0xFF));
  out.push_back(static_cast<char>((v >> 8) & 0xFF));
}

// GIF's LZW: codes 0-255 are the palette indices, 256 clears the table, 257 ends the data;
// strings get codes from 258 up to 4095, and codes are as wide as the largest one assigned
// (9 to 12 bits), packed least significant bit first.
constexpr int kClearCode = 256, kEndCode = 257, kFirstCode = 258, kMaxCodes = 4096, kMinCodeSize = 8;

// Strings known to the encoder, each a known string (`prefix` code) plus one index; an
// open-addressed hash table that is cheap to clear, which happens every few thousand codes.
class CodeTable {
 public:
  void Clear() {
    std::fill(keys_.begin(), keys_.end(), -1);
    next_ = kFirstCode;
  }
  // The slot holding (prefix, index), or the empty slot where it would go.
  int Slot(int prefix, uint8_t index) const {
    const int32_t key = (prefix << 8) | index;
    uint32_t slot = (static_cast<uint32_t>(key) * 2654435761u) >> (32 - kSlotBits);
    while (keys_[slot] != -1 && keys_[slot] != key) slot = (slot + 1) & (kSlots - 1);
    return static_cast<int>(slot);
  }
  bool Holds(int slot) const { return keys_[slot] != -1; }
  int Code(int slot) const { return codes_[slot]; }
  bool Full() const { return next_ == kMaxCodes; }
  // Gives (prefix, index) the next free code, at the empty `slot` Slot() returned; returns it.
  int Insert(int slot, int prefix, uint8_t index) {
    keys_[slot] = (prefix << 8) | index;
    codes_[slot] = static_cast<uint16_t>(next_);
    return next_++;
  }
  int next() const { return next_; }

 private:
  static constexpr int kSlotBits = 13;
  static constexpr int kSlots = 1 << kSlotBits;  // twice the codes: probe sequences stay short
  std::vector<int32_t> keys_ = std::vector<int32_t>(kSlots, -1);
  std::vector<uint16_t> codes_ = std::vector<uint16_t>(kSlots, 0);
  int next_ = kFirstCode;
};

class BitWriter {
 public:
  void Put(int code, int width) {
    buffer_ |= static_cast<uint32_t>(code) << count_;
    count_ += width;
    while (count_ >= 8) {
      bytes_.push_back(static_cast<char>(buffer_ & 0xFF));
      buffer_ >>= 8;
      count_ -= 8;
    }
  }
  std::string Finish() {
    if (count_ > 0) bytes_.push_back(static_cast<char>(buffer_ & 0xFF));
    return std::move(bytes_);
  }

 private:
  std::string bytes_;
  uint32_t buffer_ = 0;
  int count_ = 0;
};

std::string LzwEncode(const std::vector<uint8_t>& indices) {
  CodeTable table;
  BitWriter bits;
  int width = kMinCodeSize + 1;
  bits.Put(kClearCode, width);
  int prefix = indices[0];
  for (size_t i = 1; i < indices.size(); ++i) {
    const uint8_t index = indices[i];
    const int slot = table.Slot(prefix, index);
    if (table.Holds(slot)) {
      prefix = table.Code(slot);
      continue;
    }
    bits.Put(prefix, width);
    if (!table.Full()) {
      // a code of 2^width needs one bit more
      if (table.Insert(slot, prefix, index) == (1 << width)) ++width;
    } else {
      bits.Put(kClearCode, width);
      table.Clear();
      width = kMinCodeSize + 1;
    }
    prefix = index;
  }
  bits.Put(prefix, width);
  // Reading that last code, the decoder assigns one more code, as it does for every code but
  // the first after a clear; the end code must be as wide as the decoder then expects.
  if (!table.Full() && table.next() == (1 << width)) ++width;
  bits.Put(kEndCode, width);
  return bits.Finish();
}

// Image data is a sequence of sub-blocks of at most 255 bytes, each after its length, and an
// empty one.
void AppendSubBlocks(const std::string& data, std::string& out) {
  for (size_t at = 0; at < data.size(); at += 255) {
    const size_t n = std::min<size_t>(255, data.size() - at);
    out.push_back(static_cast<char>(n));
    out.append(data, at, n);
  }
  out.push_back('\0');
}

}  // namespace

const std::array<Rgb, 256>& GifPalette() {
  static const std::array<Rgb, 256> palette = [] {
    std::array<Rgb, 256> p{};  // entries past the cube stay black
    for (int r = 0; r < kRedLevels; ++r) {
      for (int g = 0; g < kGreenLevels; ++g) {
        for (int b = 0; b < kBlueLevels; ++b) {
          p[(r * kGreenLevels + g) * kBlueLevels + b] = {LevelValue(r, kRedLevels), LevelValue(g, kGreenLevels),
                                                         LevelValue(b, kBlueLevels)};
        }
      }
    }
    return p;
  }();
  return palette;
}

GifWriter::GifWriter(std::string path, int width, int height, int delay_cs)
    : path_(std::move(path)), width_(width), height_(height), delay_cs_(delay_cs) {
  if (width < 1 || height < 1 || width > 65535 || height > 65535) {
    throw InputError(path_ + ": a GIF is 1 to 65535 pixels on a side, not " + std::to_string(width) + "x" +
                     std::to_string(height));
  }
  if (delay_cs < 1 || delay_cs > 65535) {
    throw InputError(path_ + ": a GIF frame shows for 1 to 65535 hundredths of a second, not " +
                     std::to_string(delay_cs));
  }
  bytes_ = "GIF89a";
  // logical screen: global palette of 2^(7+1) colours, 8 bits per primary, background index 0
  AppendU16(bytes_, width);
  AppendU16(bytes_, height);
  bytes_ += {'\xF7', '\0', '\0'};
  for (const Rgb& c : GifPalette()) bytes_ += {static_cast<char>(c.r), static_cast<char>(c.g), static_cast<char>(c.b)};
  // NETSCAPE2.0 application extension: loop count 0, i.e. forever
  bytes_ += {'\x21', '\xFF', '\x0B'};
  bytes_ += "NETSCAPE2.0";
  bytes_ += {'\x03', '\x01', '\0', '\0', '\0'};
}

void GifWriter::AddFrame(const Image& frame) {
  FLSD_DEMAND(!closed_);
  if (frame.width != width_ || frame.height != height_) {
    throw InputError(path_ + ": a frame of " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " in a " + std::to_string(width_) + "x" + std::to_string(height_) + " GIF");
  }
  indices_.resize(static_cast<size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const Rgb c = frame.at(x, y);
      const int t = kBayer[y % 4][x % 4];
      indices_[static_cast<size_t>(y) * width_ + x] = static_cast<uint8_t>(
          (DitheredLevel(c.r, kRedLevels, t) * kGreenLevels + DitheredLevel(c.g, kGreenLevels, t)) * kBlueLevels +
          DitheredLevel(c.b, kBlueLevels, t));
    }
  }
  // graphic control extension: leave the frame in place (disposal 1), show it delay_cs_
  bytes_ += {'\x21', '\xF9', '\x04', '\x04'};
  AppendU16(bytes_, delay_cs_);
  bytes_ += {'\0', '\0'};
  // image descriptor: the whole screen, global palette, not interlaced
  bytes_ += '\x2C';
  AppendU16(bytes_, 0);
  AppendU16(bytes_, 0);
  AppendU16(bytes_, width_);
  AppendU16(bytes_, height_);
  bytes_ += '\0';
  bytes_ += static_cast<char>(kMinCodeSize);
  AppendSubBlocks(LzwEncode(indices_), bytes_);
  ++frames_;
}

void GifWriter::Close() {
  FLSD_DEMAND(!closed_);
  closed_ = true;
  if (frames_ == 0) throw InputError(path_ + ": a GIF needs a frame");
  bytes_ += '\x3B';  // trailer
  WriteFileAtomically(path_, bytes_);
}

// ---- MP4 ----

bool CommandExists(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  const std::string dirs = path;
  for (size_t begin = 0; begin <= dirs.size();) {
    size_t end = dirs.find(':', begin);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = dirs.substr(begin, end - begin);
    if (!dir.empty() && ::access((dir + "/" + name).c_str(), X_OK) == 0) return true;
    begin = end + 1;
  }
  return false;
}

namespace {

std::string ShellQuote(const std::string& s) {
  std::string quoted = "'";
  for (char c : s) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Debian's ffmpeg has libx264; builds without it still have the native MPEG-4 part 2 encoder.
std::string FfmpegVideoCodec() {
  FILE* list = ::popen("ffmpeg -hide_banner -encoders 2>/dev/null", "r");
  if (list == nullptr) return "mpeg4";
  std::string text;
  char chunk[4096];
  for (size_t n; (n = std::fread(chunk, 1, sizeof(chunk), list)) > 0;) text.append(chunk, n);
  ::pclose(list);
  return text.find(" libx264 ") != std::string::npos ? "libx264" : "mpeg4";
}

}  // namespace

Mp4Writer::Mp4Writer(std::string path, int width, int height, double fps)
    : path_(std::move(path)), temp_path_(path_ + ".tmp"), width_(width), height_(height) {
  if (!CommandExists("ffmpeg")) {
    throw InputError(path_ + ": writing .mp4 needs the ffmpeg command (apt install ffmpeg); .gif needs nothing");
  }
  if (width < 2 || height < 2 || width % 2 != 0 || height % 2 != 0) {
    throw InputError(path_ + ": an .mp4 needs an even width and height (yuv420p), not " + std::to_string(width) + "x" +
                     std::to_string(height));
  }
  char rate[32];
  std::snprintf(rate, sizeof(rate), "%.6g", fps);
  const std::string command = "ffmpeg -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgb24 -s " +
                              std::to_string(width) + "x" + std::to_string(height) + " -r " + rate +
                              " -i - -pix_fmt yuv420p -vcodec " + FfmpegVideoCodec() + " -f mp4 " +
                              ShellQuote(temp_path_);
  // If ffmpeg dies, writing to the pipe must fail with EPIPE rather than kill this process.
  previous_sigpipe_ = std::signal(SIGPIPE, SIG_IGN);
  pipe_ = ::popen(command.c_str(), "w");
  if (pipe_ == nullptr) {
    std::signal(SIGPIPE, previous_sigpipe_);
    throw InputError(path_ + ": cannot start ffmpeg");
  }
}

Mp4Writer::~Mp4Writer() {
  if (pipe_ == nullptr) return;
  Stop();
  std::remove(temp_path_.c_str());
}

int Mp4Writer::Stop() {
  const int status = ::pclose(pipe_);
  pipe_ = nullptr;
  std::signal(SIGPIPE, previous_sigpipe_);
  return status;
}

void Mp4Writer::AddFrame(const Image& frame) {
  FLSD_DEMAND(pipe_ != nullptr);
  if (frame.width != width_ || frame.height != height_) {
    throw InputError(path_ + ": a frame of " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " in a " + std::to_string(width_) + "x" + std::to_string(height_) + " video");
  }
  if (std::fwrite(frame.rgb.data(), 1, frame.rgb.size(), pipe_) != frame.rgb.size()) {
    throw InputError(path_ + ": ffmpeg stopped reading frames (see its message above)");
  }
}

void Mp4Writer::Close() {
  FLSD_DEMAND(pipe_ != nullptr);
  if (Stop() != 0) {
    std::remove(temp_path_.c_str());
    throw InputError(path_ + ": ffmpeg failed (see its message above)");
  }
  std::error_code ec;
  std::filesystem::rename(temp_path_, path_, ec);
  if (ec) {
    std::remove(temp_path_.c_str());
    throw InputError(path_ + ": cannot replace with " + temp_path_ + ": " + ec.message());
  }
}

}  // namespace flsd
