#include "render/image.h"

#include <gif_lib.h>
#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <utility>

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

// giflib writes the encoded file through this, into the writer's memory.
int AppendToString(GifFileType* gif, const GifByteType* data, int length) {
  static_cast<std::string*>(gif->UserData)->append(reinterpret_cast<const char*>(data), length);
  return length;
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
  int error = 0;
  gif_ = EGifOpen(&bytes_, AppendToString, &error);
  if (gif_ == nullptr) throw InputError(path_ + ": giflib: " + GifErrorString(error));
  EGifSetGifVersion(gif_, true);
  std::array<GifColorType, 256> colours;
  for (size_t i = 0; i < colours.size(); ++i) colours[i] = {GifPalette()[i].r, GifPalette()[i].g, GifPalette()[i].b};
  ColorMapObject* palette = GifMakeMapObject(static_cast<int>(colours.size()), colours.data());
  const bool written = palette != nullptr && EGifPutScreenDesc(gif_, width, height, 8, 0, palette) == GIF_OK;
  GifFreeMapObject(palette);
  // NETSCAPE2.0 application extension: loop count 0, i.e. forever
  const GifByteType loop[] = {1, 0, 0};
  Check(written && EGifPutExtensionLeader(gif_, APPLICATION_EXT_FUNC_CODE) == GIF_OK &&
        EGifPutExtensionBlock(gif_, 11, reinterpret_cast<const GifByteType*>("NETSCAPE2.0")) == GIF_OK &&
        EGifPutExtensionBlock(gif_, sizeof loop, loop) == GIF_OK && EGifPutExtensionTrailer(gif_) == GIF_OK);
}

GifWriter::~GifWriter() {
  if (gif_ != nullptr) EGifCloseFile(gif_, nullptr);  // not closed: nothing is written
}

void GifWriter::Check(bool ok) const {
  if (!ok) throw InputError(path_ + ": giflib: " + GifErrorString(gif_->Error));
}

void GifWriter::AddFrame(const Image& frame) {
  FLSD_DEMAND(gif_ != nullptr);
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
  // graphic control extension: leave the frame in place, show it delay_cs_
  GraphicsControlBlock control{};
  control.DisposalMode = DISPOSE_DO_NOT;
  control.DelayTime = delay_cs_;
  control.TransparentColor = NO_TRANSPARENT_COLOR;
  GifByteType extension[4];
  const size_t size = EGifGCBToExtension(&control, extension);
  // the whole screen, global palette, not interlaced
  Check(EGifPutExtension(gif_, GRAPHICS_EXT_FUNC_CODE, static_cast<int>(size), extension) == GIF_OK &&
        EGifPutImageDesc(gif_, 0, 0, width_, height_, false, nullptr) == GIF_OK &&
        EGifPutLine(gif_, indices_.data(), static_cast<int>(indices_.size())) == GIF_OK);
  ++frames_;
}

void GifWriter::Close() {
  FLSD_DEMAND(gif_ != nullptr);
  GifFileType* gif = std::exchange(gif_, nullptr);
  int error = 0;
  if (EGifCloseFile(gif, &error) != GIF_OK) throw InputError(path_ + ": giflib: " + GifErrorString(error));
  if (frames_ == 0) throw InputError(path_ + ": a GIF needs a frame");
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
