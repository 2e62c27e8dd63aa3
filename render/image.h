#pragma once
// RGB images and the files `flsd render` writes: PNG (libpng), animated GIF (written here, no
// library) and MP4 (through the ffmpeg command, when it is installed). Every file appears
// atomically: a failed write leaves the old file or none, never a torn one. Failures throw
// InputError naming the path.

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

struct GifFileType;  // giflib's encoder (gif_lib.h)

namespace flsd {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

// 8-bit RGB pixels, rows top first, no padding: pixel (x, y) is rgb[3 * (y * width + x)].
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;

  Image() = default;
  Image(int w, int h, Rgb fill = {});
  Rgb at(int x, int y) const;
  void set(int x, int y, Rgb c);
};

// Paints the rectangle [x, x + w) x [y, y + h), clipped to the image.
void FillRect(Image& image, int x, int y, int w, int h, Rgb color);
// Copies `source` with its top-left corner at (x, y), clipped to `target`.
void Blit(const Image& source, int x, int y, Image& target);
// Writes `number` (>= 0) in a 5x7 pixel digit font, each font pixel `scale` pixels wide, its
// top-left corner at (x, y), on a `background` box one font pixel wider on every side. Returns
// the box's width.
int DrawNumber(Image& image, int x, int y, int number, int scale, Rgb color, Rgb background);

// Throws InputError naming the path if the file cannot be written.
void WritePng(const Image& image, const std::string& path);

// An animation written frame by frame; nothing is written until Close().
class VideoWriter {
 public:
  virtual ~VideoWriter() = default;
  // Throws InputError if the frame's size is not the video's.
  virtual void AddFrame(const Image& frame) = 0;
  // Finishes the file and moves it into place. Throws InputError naming the path on failure.
  virtual void Close() = 0;
};

// The GIF palette: a 6 x 7 x 6 colour cube (green, to which the eye is most sensitive, gets the
// extra level) and four black entries to fill 256. Colours on the cube are stored exactly; others
// are ordered-dithered between the nearest cube levels, which holds still from frame to frame
// (error diffusion would make the floor shimmer) and keeps smooth shading free of bands.
const std::array<Rgb, 256>& GifPalette();

// An animated GIF89a that loops forever: one global palette, every frame full size, encoded by
// giflib. The file is assembled in memory (a few MB for seconds of video) and written at Close();
// a writer destroyed without Close() writes nothing. Not copyable: it owns giflib's encoder.
class GifWriter final : public VideoWriter {
 public:
  // delay_cs: how long each frame shows, in hundredths of a second (GIF's unit), 1 to 65535.
  GifWriter(std::string path, int width, int height, int delay_cs);
  ~GifWriter() override;
  GifWriter(const GifWriter&) = delete;
  GifWriter& operator=(const GifWriter&) = delete;
  void AddFrame(const Image& frame) override;
  void Close() override;

 private:
  // Throws InputError naming the file and giflib's error unless `ok`.
  void Check(bool ok) const;

  std::string path_;
  int width_, height_, delay_cs_;
  std::string bytes_;
  GifFileType* gif_ = nullptr;  // the encoder, until Close()
  std::vector<uint8_t> indices_;  // the frame being encoded, one palette index per pixel
  int frames_ = 0;
};

// An H.264 MP4 (MPEG-4 part 2 if this ffmpeg lacks libx264) encoded by an ffmpeg process that
// reads raw frames on a pipe. Width and height must be even (yuv420p). A writer destroyed without
// Close() stops ffmpeg and removes its partial file. Not copyable: it owns the process.
class Mp4Writer final : public VideoWriter {
 public:
  // Throws InputError if ffmpeg is not installed or cannot be started.
  Mp4Writer(std::string path, int width, int height, double fps);
  ~Mp4Writer() override;
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;
  void AddFrame(const Image& frame) override;
  void Close() override;

 private:
  // Closes the pipe, waits for ffmpeg and returns its pclose() status.
  int Stop();

  std::string path_, temp_path_;
  int width_, height_;
  FILE* pipe_ = nullptr;
  void (*previous_sigpipe_)(int) = nullptr;
};

// True if an executable `name` is on PATH.
bool CommandExists(const std::string& name);

}  // namespace flsd
