#include "render/offscreen_renderer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <set>

#include "sim/env.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::InputErrorMessage;

constexpr int kWidth = 160, kHeight = 120;

// The A1 standing in its default pose at the origin, at rest.
Env StandingRobot(const mjModel& model) {
  EnvConfig config;
  config.randomization.DisableAll();
  config.reset.base_velocity = 0.0;
  config.reset.joint_pos_scale = {1.0, 1.0};
  Env env(model, config, 1);
  env.Reset();
  return env;
}

struct Centroid {
  double x = 0.0, y = 0.0;
  int pixels = 0;
};

// The light grey trunk (rgba 0.75 0.75 0.78): bright and neutral, where the floor is a dark
// blue-grey checker and the sky black.
Centroid TrunkPixels(const Image& image) {
  Centroid c;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const Rgb p = image.at(x, y);
      const int lo = std::min({p.r, p.g, p.b}), hi = std::max({p.r, p.g, p.b});
      if (lo > 140 && hi - lo < 30) {
        c.x += x;
        c.y += y;
        ++c.pixels;
      }
    }
  }
  if (c.pixels > 0) {
    c.x /= c.pixels;
    c.y /= c.pixels;
  }
  return c;
}

// Mean of |a - b| over the channels of a size x size square at (x, y) and (u, v).
double RegionDifference(const Image& a, int x, int y, const Image& b, int u, int v, int size) {
  double sum = 0.0;
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const Rgb p = a.at(x + i, y + j), q = b.at(u + i, v + j);
      sum += std::abs(p.r - q.r) + std::abs(p.g - q.g) + std::abs(p.b - q.b);
    }
  }
  return sum / (3.0 * size * size);
}

TEST(OffscreenRenderer, ShowsTheRobotAtTheCentreOverTheFloor) {
  const MjModelPtr model = LoadMjModel("robot/a1/scene.xml");
  Env env = StandingRobot(*model);
  OffscreenRenderer renderer(*model, kWidth, kHeight);
  const Image image = renderer.Render(env.data());
  ASSERT_EQ(image.width, kWidth);
  ASSERT_EQ(image.height, kHeight);

  std::set<int> colours;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const Rgb p = image.at(x, y);
      colours.insert((p.r << 16) | (p.g << 8) | p.b);
    }
  }
  EXPECT_GT(colours.size(), 100u) << "a picture, not a blank";

  // the trunk, where the camera looks, against the floor in the bottom left corner
  EXPECT_GT(RegionDifference(image, kWidth / 2 - 6, kHeight / 2 - 6, image, 0, kHeight - 12, 12), 40.0);
  const Centroid trunk = TrunkPixels(image);
  EXPECT_GT(trunk.pixels, 80);
  EXPECT_NEAR(trunk.x, kWidth / 2.0, 0.1 * kWidth);
  EXPECT_NEAR(trunk.y, kHeight / 2.0, 0.1 * kHeight);
  // the floor's bottom rows are lit blue-grey, the sky's top rows black
  const Rgb floor = image.at(2, kHeight - 3), sky = image.at(2, 2);
  EXPECT_GT(floor.b, floor.r + 10) << int(floor.r) << "," << int(floor.g) << "," << int(floor.b);
  EXPECT_EQ(sky, (Rgb{0, 0, 0}));
}

TEST(OffscreenRenderer, FollowsTheRobotWhenItMoves) {
  const MjModelPtr model = LoadMjModel("robot/a1/scene.xml");
  Env env = StandingRobot(*model);
  OffscreenRenderer renderer(*model, kWidth, kHeight);
  const Image here = renderer.Render(env.data());
  // 1 m forward and 0.3 m to the side: the checker (0.5 m squares) no longer lines up
  env.data().qpos[env.index().root_qpos + 0] += 1.0;
  env.data().qpos[env.index().root_qpos + 1] += 0.3;
  mj_forward(&env.model(), &env.data());
  const Image there = renderer.Render(env.data());

  const Centroid a = TrunkPixels(here), b = TrunkPixels(there);
  ASSERT_GT(a.pixels, 80);
  EXPECT_NEAR(b.pixels, a.pixels, 0.1 * a.pixels);
  EXPECT_NEAR(b.x, a.x, 2.0);
  EXPECT_NEAR(b.y, a.y, 2.0);
  EXPECT_LT(RegionDifference(here, kWidth / 2 - 10, kHeight / 2 - 10, there, kWidth / 2 - 10, kHeight / 2 - 10, 20),
            10.0)
      << "the robot looks the same from the camera that follows it";
  EXPECT_GT(RegionDifference(here, 0, kHeight - 30, there, 0, kHeight - 30, 30), 5.0)
      << "but the floor under it has moved";
}

TEST(OffscreenRenderer, APictureLargerThanTheOffscreenBufferIsAnInputError) {
  const MjModelPtr model = LoadMjModel("robot/a1/scene.xml");
  EXPECT_THAT(InputErrorMessage([&] { OffscreenRenderer renderer(*model, 1920, 1080); }),
              AllOf(HasSubstr("1920x1080"), HasSubstr("1280x720"), HasSubstr("offwidth")));
}

}  // namespace
}  // namespace flsd
