#include "render/image.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "tests/common/test_support.h"
#include "tests/render/gif_reader.h"

namespace flsd {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::DecodedGif;
using testutil::InputErrorMessage;
using testutil::UniqueTempPath;

using testutil::ReadFile;
using testutil::ScratchFile;

DecodedGif WriteAndDecode(const std::string& path, const std::vector<Image>& frames, int delay_cs) {
  GifWriter gif(path, frames.at(0).width, frames.at(0).height, delay_cs);
  for (const Image& frame : frames) gif.AddFrame(frame);
  gif.Close();
  return testutil::DecodeGif(ReadFile(path));
}

// Every pixel a random palette colour: nearly one LZW code per pixel, so the 4096-code table
// fills within a few thousand pixels.
Image PaletteNoise(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> cube_entry(0, 6 * 7 * 6 - 1);
  Image image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) image.set(x, y, GifPalette()[cube_entry(rng)]);
  }
  return image;
}

void ExpectSameColors(const DecodedGif& gif, int frame, const Image& expected) {
  int wrong = 0;
  for (int y = 0; y < expected.height; ++y) {
    for (int x = 0; x < expected.width; ++x) wrong += !(gif.Color(gif.frames.at(frame), x, y) == expected.at(x, y));
  }
  EXPECT_EQ(wrong, 0) << "pixels of frame " << frame << " that changed colour";
}

TEST(Png, RoundTripsEveryPixelExactly) {
  Image image(7, 5);
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 7; ++x) {
      image.set(x, y, {static_cast<uint8_t>(36 * x + 1), static_cast<uint8_t>(50 * y + 3),
                       static_cast<uint8_t>(255 - 9 * (x + 7 * y))});
    }
  }
  ScratchFile file(".png");
  WritePng(image, file.path());

  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  ASSERT_TRUE(png_image_begin_read_from_file(&png, file.path().c_str())) << png.message;
  EXPECT_EQ(png.width, 7u);
  EXPECT_EQ(png.height, 5u);
  png.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(png));
  ASSERT_TRUE(png_image_finish_read(&png, nullptr, pixels.data(), 0, nullptr)) << png.message;
  EXPECT_EQ(pixels, image.rgb);
}

TEST(Png, AFolderThatDoesNotExistIsAnInputErrorNamingThePath) {
  const std::string path = UniqueTempPath("missing") + "/picture.png";
  EXPECT_THAT(InputErrorMessage([&] { WritePng(Image(2, 2), path); }), HasSubstr(path));
}

TEST(GifPalette, IsASixBySevenBySixCubeThenBlack) {
  const auto& palette = GifPalette();
  EXPECT_EQ(palette[0], (Rgb{0, 0, 0}));
  EXPECT_EQ(palette[1], (Rgb{0, 0, 51}));    // blue: 6 levels, 51 apart
  EXPECT_EQ(palette[6], (Rgb{0, 43, 0}));    // green: 7 levels, 42.5 apart
  EXPECT_EQ(palette[42], (Rgb{51, 0, 0}));   // red: 6 levels
  EXPECT_EQ(palette[251], (Rgb{255, 255, 255}));
  for (int i = 252; i < 256; ++i) EXPECT_EQ(palette[i], (Rgb{0, 0, 0}));
}

TEST(Gif, TwoFramesOfNoiseAndFlatColourDecodeToTheSameColours) {
  const Image noise = PaletteNoise(100, 80, 7);
  const Image flat(100, 80, GifPalette()[123]);
  ScratchFile file(".gif");
  const DecodedGif gif = WriteAndDecode(file.path(), {noise, flat}, 7);

  EXPECT_EQ(ReadFile(file.path()).substr(0, 6), "GIF89a");
  EXPECT_EQ(gif.width, 100);
  EXPECT_EQ(gif.height, 80);
  EXPECT_EQ(gif.loop_count, 0) << "0 loops forever";
  ASSERT_EQ(gif.palette.size(), 256u);
  for (int i = 0; i < 256; ++i) EXPECT_EQ(gif.palette[i], GifPalette()[i]) << "entry " << i;
  ASSERT_EQ(gif.frames.size(), 2u);
  EXPECT_TRUE(gif.trailer);
  for (const auto& frame : gif.frames) {
    EXPECT_EQ(frame.delay_cs, 7);
    EXPECT_EQ(frame.width, 100);
    EXPECT_EQ(frame.height, 80);
  }
  ExpectSameColors(gif, 0, noise);
  ExpectSameColors(gif, 1, flat);
  // 8000 pixels of noise need over 7000 codes: the table (3838 strings) fills at least once.
  EXPECT_GE(gif.frames[0].clear_codes, 2);
  // A flat frame is about 130 ever longer strings, each code the one just defined.
  EXPECT_EQ(gif.frames[1].clear_codes, 1);
}

TEST(Gif, EdgeSizesRoundTrip) {
  // one pixel; one row; and a pattern with a period of 252 pixels, whose repeats make strings of
  // every length
  Image pixel(1, 1, GifPalette()[200]);
  Image row = PaletteNoise(300, 1, 3);
  Image stripes(512, 64);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 512; ++x) stripes.set(x, y, GifPalette()[(x * 37 + y * 11) % 252]);
  }
  for (const Image& image : {pixel, row, stripes}) {
    ScratchFile file(".gif");
    const DecodedGif gif = WriteAndDecode(file.path(), {image}, 4);
    ASSERT_EQ(gif.frames.size(), 1u);
    ExpectSameColors(gif, 0, image);
  }
}

TEST(Gif, ColoursOffThePaletteAreDitheredToTheirMeanOverEachFourByFourTile) {
  const std::vector<Rgb> colours = {{128, 128, 128}, {191, 64, 90}, {20, 230, 140}, {77, 102, 128}};
  for (const Rgb& c : colours) {
    const Image flat(16, 16, c);
    ScratchFile file(".gif");
    const DecodedGif gif = WriteAndDecode(file.path(), {flat}, 4);
    double sum[3] = {0, 0, 0};
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 4; ++x) {
        const Rgb d = gif.Color(gif.frames.at(0), x, y);
        sum[0] += d.r;
        sum[1] += d.g;
        sum[2] += d.b;
      }
    }
    // a 16-step dither reproduces a level within 1/16 of a level step (51 or 42.5)
    EXPECT_NEAR(sum[0] / 16, c.r, 51.0 / 16) << "red of " << int(c.r) << "," << int(c.g) << "," << int(c.b);
    EXPECT_NEAR(sum[1] / 16, c.g, 42.5 / 16) << "green";
    EXPECT_NEAR(sum[2] / 16, c.b, 51.0 / 16) << "blue";
  }
}

TEST(Gif, AFrameOfAnotherSizeOrNoFrameAtAllIsAnInputError) {
  ScratchFile file(".gif");
  GifWriter gif(file.path(), 8, 6, 4);
  EXPECT_THAT(InputErrorMessage([&] { gif.AddFrame(Image(6, 8)); }),
              AllOf(HasSubstr(file.path()), HasSubstr("6x8"), HasSubstr("8x6")));
  EXPECT_THAT(InputErrorMessage([&] { gif.Close(); }), HasSubstr("needs a frame"));
  EXPECT_FALSE(std::filesystem::exists(file.path()));
}

TEST(Mp4, WithoutFfmpegSaysHowToGetItAndOtherwiseWritesAnMp4) {
  ScratchFile file(".mp4");
  if (!CommandExists("ffmpeg")) {
    EXPECT_THAT(InputErrorMessage([&] { Mp4Writer video(file.path(), 32, 24, 25.0); }),
                AllOf(HasSubstr("ffmpeg"), HasSubstr("apt install ffmpeg"), HasSubstr(".gif needs nothing")));
    return;
  }
  Mp4Writer video(file.path(), 32, 24, 25.0);
  for (int i = 0; i < 3; ++i) video.AddFrame(PaletteNoise(32, 24, i));
  video.Close();
  EXPECT_EQ(ReadFile(file.path()).substr(4, 4), "ftyp");
}

TEST(DrawNumber, DrawsFiveBySevenDigitsOnABox) {
  const Rgb white{255, 255, 255}, box{10, 20, 30}, paper{100, 100, 100};
  Image image(40, 24, paper);
  const int width = DrawNumber(image, 2, 3, 17, 2, white, box);
  EXPECT_EQ(width, (2 * 6 + 1) * 2);  // two 5-wide digits, gaps of 1, margins of 1, doubled
  EXPECT_EQ(image.at(1, 3), paper);
  EXPECT_EQ(image.at(2, 3), box);                   // the margin
  EXPECT_EQ(image.at(2 + width - 1, 3 + 17), box);  // the box's last pixel: 9 font rows of 2
  EXPECT_EQ(image.at(2 + width, 3), paper);
  // '1' has its stem in font column 2 of rows 0 to 6; '7' a full top bar
  EXPECT_EQ(image.at(2 + 2 * (1 + 2), 3 + 2 * (1 + 3)), white);
  EXPECT_EQ(image.at(2 + 2 * (1 + 0), 3 + 2 * (1 + 3)), box);
  for (int col = 0; col < 5; ++col) EXPECT_EQ(image.at(2 + 2 * (7 + col), 3 + 2), white) << col;
}

}  // namespace
}  // namespace flsd
