#include "render/skill_render.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <png.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "render/image.h"
#include "tests/common/test_support.h"
#include "tests/render/gif_reader.h"

namespace flsd {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::InputErrorMessage;
using testutil::UniqueTempPath;

// Small and short: a frame costs the software renderer about 0.1 s.
RenderOptions ShortRender(const std::string& output) {
  RenderOptions options;
  options.library = "models/a1_flsd.safetensors";
  options.skill = 3;
  options.seconds = 0.5;
  options.fps = 10;
  options.width = 160;
  options.height = 120;
  options.output = output;
  return options;
}

using testutil::ReadFile;
using testutil::ScratchFile;

Image ReadPng(const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) throw std::runtime_error(png.message);
  png.format = PNG_FORMAT_RGB;
  Image image(static_cast<int>(png.width), static_cast<int>(png.height));
  if (!png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr)) throw std::runtime_error(png.message);
  return image;
}

TEST(RunRender, WritesAGifOfFiveFramesForHalfASecondAtTenFps) {
  ScratchFile file(".gif");
  EXPECT_EQ(RunRender(ShortRender(file.path())), 0);
  const std::string bytes = ReadFile(file.path());
  ASSERT_EQ(bytes.substr(0, 6), "GIF89a");
  const testutil::DecodedGif gif = testutil::DecodeGif(bytes);
  EXPECT_EQ(gif.width, 160);
  EXPECT_EQ(gif.height, 120);
  EXPECT_EQ(gif.loop_count, 0);
  EXPECT_TRUE(gif.trailer);
  ASSERT_EQ(gif.frames.size(), 5u) << "frames at 0, 0.1, ..., 0.4 s";
  for (const auto& frame : gif.frames) EXPECT_EQ(frame.delay_cs, 10);
  EXPECT_NE(gif.frames.front().indices, gif.frames.back().indices) << "the robot moves";
}

TEST(RunRender, WritesTheLastFrameAsAPng) {
  ScratchFile file(".png");
  EXPECT_EQ(RunRender(ShortRender(file.path())), 0);
  const Image still = ReadPng(file.path());
  EXPECT_EQ(still.width, 160);
  EXPECT_EQ(still.height, 120);
}

TEST(RunRender, AContactSheetTilesEverySkillFourAcrossWithItsNumber) {
  ScratchFile file(".png");
  RenderOptions options = ShortRender(file.path());
  options.contact_sheet = true;
  options.seconds = 0.2;
  EXPECT_EQ(RunRender(options), 0);
  const Image sheet = ReadPng(file.path());
  // 15 skills: 4 rows of up to 4 tiles of 160x120 with 4-pixel gaps
  ASSERT_EQ(sheet.width, 4 * 164 + 4);
  ASSERT_EQ(sheet.height, 4 * 124 + 4);
  const Rgb background{20, 20, 20}, label_box{30, 30, 30}, white{255, 255, 255};
  EXPECT_EQ(sheet.at(0, 0), background);
  EXPECT_EQ(sheet.at(4 + 160, 60), background) << "the gap between the first two tiles";
  // Labels at (8, 8) in each tile, one pixel per font pixel at this height: the box's corner,
  // the top of tile 0's '0' (font column 1) and of the '1' of tile 13's "13" (font column 2).
  EXPECT_EQ(sheet.at(4 + 8, 4 + 8), label_box);
  EXPECT_EQ(sheet.at(4 + 8 + 1 + 1, 4 + 8 + 1), white);
  const int tile13_x = 4 + 1 * 164, tile13_y = 4 + 3 * 124;
  EXPECT_EQ(sheet.at(tile13_x + 8 + 1 + 2, tile13_y + 8 + 1), white);
  EXPECT_EQ(sheet.at(tile13_x + 8 + 1 + 0, tile13_y + 8 + 1), label_box);
  EXPECT_EQ(sheet.at(4 + 2 * 164 + 8, 4 + 3 * 124 + 8), label_box) << "tile 14";
  EXPECT_EQ(sheet.at(4 + 3 * 164 + 8, 4 + 3 * 124 + 8), background) << "no tile 15";
}

TEST(RunRender, ASkillOutOfRangeIsAnInputErrorNamingTheRange) {
  ScratchFile file(".gif");
  RenderOptions options = ShortRender(file.path());
  options.skill = 15;
  EXPECT_THAT(InputErrorMessage([&] { RunRender(options); }),
              AllOf(HasSubstr("skill 15"), HasSubstr("0 to 14"), HasSubstr("a1_flsd.safetensors")));
  options.skill = -1;
  EXPECT_THAT(InputErrorMessage([&] { RunRender(options); }), HasSubstr("0 to 14"));
  EXPECT_FALSE(std::filesystem::exists(file.path()));
}

TEST(RunRender, AnUnknownExtensionIsAnInputErrorListingTheSupportedOnes) {
  const std::string path = UniqueTempPath("video.avi");
  EXPECT_THAT(InputErrorMessage([&] { RunRender(ShortRender(path)); }),
              AllOf(HasSubstr(path), HasSubstr(".gif, .mp4 or .png")));
  RenderOptions sheet = ShortRender(UniqueTempPath("sheet.gif"));
  sheet.contact_sheet = true;
  EXPECT_THAT(InputErrorMessage([&] { RunRender(sheet); }), HasSubstr("contact sheet is a .png"));
}

TEST(RunRender, OptionsOutOfRangeAreInputErrors) {
  RenderOptions options = ShortRender(UniqueTempPath("out.gif"));
  options.fps = 60;
  EXPECT_THAT(InputErrorMessage([&] { RunRender(options); }), HasSubstr("fps must be 1 to 50"));
  options = ShortRender(UniqueTempPath("out.gif"));
  options.seconds = 0.0;
  EXPECT_THAT(InputErrorMessage([&] { RunRender(options); }), HasSubstr("seconds must be above 0"));
  options = ShortRender(UniqueTempPath("out.gif"));
  options.width = 4000;
  EXPECT_THAT(InputErrorMessage([&] { RunRender(options); }), HasSubstr("offscreen buffer"));
}

}  // namespace
}  // namespace flsd
